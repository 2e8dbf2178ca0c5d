# Stage "classification" (Sects. 4.3-5.2): the objective f of eq. (11) along sweeps of the
# polynomial profile (Figs. 4, 5), the Fourier shape optimisation (Fig. 6), the a-priori
# decision tree (Fig. 8) and the (y2'', y3'') maps of f and case (Figs. 10, 11).  The maps
# are computed in `shards` row blocks (one job each) and gathered; every map point is
# verified against a simulation (verify_fig10_11).  README.md, "Steady state and
# classification".

CLASSIFICATION = config["stages"]["classification"]
SWEEPS = sorted(CLASSIFICATION["sweeps"])
MAPS = sorted(CLASSIFICATION["maps"])
MAP_SHARDS = CLASSIFICATION["shards"]


rule compute_sweep:
    output:
        results("classification", "{sweep}"),
    params:
        sweep=lambda wildcards: CLASSIFICATION["sweeps"][wildcards.sweep],
        polynomial=CLASSIFICATION["polynomial"],
    wildcard_constraints:
        sweep="|".join(re.escape(s) for s in SWEEPS),
    log:
        log_file("classification", "{sweep}"),
    script:
        "../scripts/compute_fig04_05.py"


rule compute_fig06:
    output:
        results("classification", "fig06"),
    params:
        fourier=CLASSIFICATION["fourier"],
    log:
        log_file("classification", "fig06"),
    script:
        "../scripts/compute_fig06.py"


rule compute_map_shard:
    output:
        shard_result("classification", "{map}"),
    params:
        map=lambda wildcards: CLASSIFICATION["maps"][wildcards.map],
        shards=MAP_SHARDS,
    wildcard_constraints:
        map="|".join(re.escape(m) for m in MAPS),
    log:
        log_file("classification", "shards/{map}_{shard}"),
    script:
        "../scripts/compute_fig10_11.py"


rule gather_map:
    input:
        lambda wildcards: shard_results("classification", wildcards.map, MAP_SHARDS),
    output:
        results("classification", "{map}"),
    params:
        map=lambda wildcards: CLASSIFICATION["maps"][wildcards.map],
    wildcard_constraints:
        map="|".join(re.escape(m) for m in MAPS),
    log:
        log_file("classification", "{map}"),
    script:
        "../scripts/compute_fig10_11.py"


rule verify_fig10_11:
    input:
        [results("classification", m) for m in MAPS],
    output:
        results("classification", "verify_fig10_11"),
    log:
        log_file("classification", "verify_fig10_11"),
    script:
        "../scripts/compute_fig10_11.py"


rule plot_fig04:
    input:
        results("classification", "fig04"),
    output:
        figure("fig04"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig04"),
    script:
        "../scripts/plot_fig04.py"


rule plot_fig05:
    input:
        results("classification", "fig05"),
    output:
        figure("fig05"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig05"),
    script:
        "../scripts/plot_fig05.py"


rule plot_fig06:
    input:
        results("classification", "fig06"),
    output:
        figure("fig06"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig06"),
    script:
        "../scripts/plot_fig06.py"


# Fig. 8 is drawn from the decision tree in selfalign/classification.py itself (no result
# file); after changing the tree: snakemake -c2 --forcerun plot_fig08.
rule plot_fig08:
    output:
        figure("fig08"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig08"),
    script:
        "../scripts/plot_fig08.py"


rule plot_fig10:
    input:
        results("classification", "fig10"),
    output:
        figure("fig10"),
    params:
        dpi=config["figures"]["dpi"],
        f_max=config["figures"]["fig10"]["f_max"],
    log:
        log_file("figures", "fig10"),
    script:
        "../scripts/plot_fig10.py"


rule plot_fig11:
    input:
        results("classification", "fig11"),
    output:
        figure("fig11"),
    params:
        dpi=config["figures"]["dpi"],
        f_max=config["figures"]["fig11"]["f_max"],
    log:
        log_file("figures", "fig11"),
    script:
        "../scripts/plot_fig11.py"


TARGETS.extend(results("classification", name) for name in SWEEPS + ["fig06"] + MAPS + ["verify_fig10_11"])
TARGETS.extend(figure(name) for name in ("fig04", "fig05", "fig06", "fig08", "fig10", "fig11"))
