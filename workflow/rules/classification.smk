# Stage "classification" (Sects. 4.3-5.2): the objective f of eq. (11) along sweeps of the
# polynomial profile (Figs. 4, 5), the Fourier shape optimisation (Fig. 6) and the
# (y2'', y3'') maps of f and case (Figs. 10, 11).  Each map is computed in `shards` row
# blocks (one job each) and gathered; every map point is verified against a simulation
# (rule verify_maps).  docs/explanation/stability.md.

CLASSIFICATION = config["stages"]["classification"]
MAPS = sorted(CLASSIFICATION["maps"])


rule compute_sweep:
    output:
        results("classification", "{sweep}"),
    params:
        sweep=lambda wildcards: CLASSIFICATION["sweeps"][wildcards.sweep],
        polynomial=CLASSIFICATION["polynomial"],
    wildcard_constraints:
        sweep="|".join(re.escape(s) for s in sorted(CLASSIFICATION["sweeps"])),
    log:
        log_file("classification", "{sweep}"),
    conda:
        ENV
    script:
        "../scripts/compute_sweep.py"


rule optimise_fourier:
    output:
        results("classification", "fig06"),
    params:
        fourier=CLASSIFICATION["fourier"],
    log:
        log_file("classification", "fig06"),
    benchmark:
        benchmark_file("classification", "fig06")
    conda:
        ENV
    script:
        "../scripts/optimise_fourier.py"


rule compute_map_shard:
    output:
        shard_result("classification", "{map}"),
    params:
        map=lambda wildcards: CLASSIFICATION["maps"][wildcards.map],
    wildcard_constraints:
        map="|".join(re.escape(m) for m in MAPS),
    log:
        log_file("classification", "shards/{map}_{shard}"),
    conda:
        ENV
    script:
        "../scripts/compute_map_shard.py"


rule gather_map:
    input:
        lambda wildcards: shard_results("classification", wildcards.map,
                                        CLASSIFICATION["maps"][wildcards.map]["shards"]),
    output:
        results("classification", "{map}"),
    params:
        map=lambda wildcards: CLASSIFICATION["maps"][wildcards.map],
    wildcard_constraints:
        map="|".join(re.escape(m) for m in MAPS),
    log:
        log_file("classification", "{map}"),
    conda:
        ENV
    script:
        "../scripts/gather_map.py"


rule verify_maps:
    input:
        [results("classification", m) for m in MAPS],
    output:
        results("classification", "verify_maps"),
    log:
        log_file("classification", "verify_maps"),
    conda:
        ENV
    script:
        "../scripts/verify_maps.py"


TARGETS.extend(results("classification", name) for name in sorted(CLASSIFICATION["sweeps"]) + ["fig06"] + MAPS)
TARGETS.append(results("classification", "verify_maps"))
