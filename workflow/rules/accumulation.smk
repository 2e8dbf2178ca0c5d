# Stage "accumulation": stopping in the high-friction zone (Sect. 7) -- the Fig. 17 sweep
# with the batched exact solver, the accumulation map of Fig. 18, the phase portraits of
# Fig. 16 (whose per-entry results also give the sketches of Figs. 14 and 15).  The Fig. 17
# sweep is computed in `shards` row blocks of y2'' (one single-process job each, like the
# classification maps) and gathered; the gathered file does not depend on the shard count.
#
# Parameters: config["stages"]["accumulation"].
# `shards` is a parameter of the shard jobs only: changing it must not rerun the other rules.
ACCUMULATION = {k: v for k, v in config["stages"]["accumulation"].items() if k not in ("scenes", "shards")}
FIG17_SHARDS = config["stages"]["accumulation"]["shards"]


def _setting_key(pair):
    return f"y2_{pair[0]:g}_y3_{pair[1]:g}"


rule compute_fig17_shard:
    output:
        shard_result("accumulation", "fig17"),
    params:
        **ACCUMULATION,
        shards=FIG17_SHARDS,
    log:
        log_file("accumulation", "shards/fig17_{shard}"),
    benchmark:
        "results/benchmarks/accumulation/shards/fig17_{shard}.tsv"
    script:
        "../scripts/compute_fig17.py"


rule gather_fig17:
    input:
        shard_results("accumulation", "fig17", FIG17_SHARDS),
    output:
        results("accumulation", "fig17"),
    params:
        **ACCUMULATION,
    log:
        log_file("accumulation", "fig17"),
    script:
        "../scripts/compute_fig17.py"


rule compute_fig16:
    output:
        results("accumulation", "fig16"),
    params:
        **ACCUMULATION,
    log:
        log_file("accumulation", "fig16"),
    script:
        "../scripts/compute_fig16.py"


rule compute_fig18:
    output:
        results("accumulation", "fig18"),
    params:
        **ACCUMULATION,
    log:
        log_file("accumulation", "fig18"),
    script:
        "../scripts/compute_fig18.py"


rule plot_fig14:
    input:
        results("accumulation", "fig16"),
    output:
        figure("fig14"),
    params:
        dpi=config["figures"]["dpi"],
        setting=_setting_key(ACCUMULATION["fig16_settings"][-1]),
    log:
        log_file("figures", "fig14"),
    script:
        "../scripts/plot_fig14.py"


rule plot_fig15:
    input:
        results("accumulation", "fig16"),
    output:
        figure("fig15"),
    params:
        dpi=config["figures"]["dpi"],
        setting=_setting_key(ACCUMULATION["fig16_settings"][-1]),
    log:
        log_file("figures", "fig15"),
    script:
        "../scripts/plot_fig15.py"


rule plot_fig16:
    input:
        results("accumulation", "fig16"),
    output:
        figure("fig16"),
    params:
        dpi=config["figures"]["dpi"],
        settings=[_setting_key(pair) for pair in ACCUMULATION["fig16_settings"]],
    log:
        log_file("figures", "fig16"),
    script:
        "../scripts/plot_fig16.py"


rule plot_fig17:
    input:
        results("accumulation", "fig17"),
    output:
        figure("fig17"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig17"),
    script:
        "../scripts/plot_fig17.py"


rule plot_fig18:
    input:
        results("accumulation", "fig18"),
    output:
        figure("fig18"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig18"),
    script:
        "../scripts/plot_fig18.py"


TARGETS.extend(results("accumulation", name) for name in ("fig16", "fig17", "fig18"))
TARGETS.extend(figure(f"fig{n}") for n in (14, 15, 16, 17, 18))
