# Stage "accumulation": stopping in the high-friction zone (Sect. 7) -- the Fig. 17 sweep
# with the batched exact solver, the accumulation map of Fig. 18, the phase portraits of
# Fig. 16 (whose per-entry results also give the sketches of Figs. 14 and 15).
#
# Parameters: config["stages"]["accumulation"].
ACCUMULATION = {k: v for k, v in config["stages"]["accumulation"].items() if k != "scenes"}


def _setting_key(pair):
    return f"y2_{pair[0]:g}_y3_{pair[1]:g}"


rule compute_fig17:
    output:
        results("accumulation", "fig17"),
    params:
        **ACCUMULATION,
    threads: 2
    log:
        log_file("accumulation", "fig17"),
    benchmark:
        "results/benchmarks/accumulation/fig17.tsv"
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
