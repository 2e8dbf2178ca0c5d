# Stage "accumulation": stopping in the high-friction zone (Sect. 7) -- the positioning sweep
# of Fig. 17 with the batched exact solver, the phase portraits of Fig. 16 (whose per-entry
# results also give Figs. 14 and 15), and the accumulation map of Fig. 18.  The Fig. 17 sweep
# is computed in `shards` row blocks of y2'' (one single-process job each) and gathered; the
# gathered file does not depend on the shard count.  Each rule gets only its own settings
# and the zone, so changing one study reruns that study alone.

ACCUMULATION = config["stages"]["accumulation"]
POSITIONING = ACCUMULATION["positioning"]


rule compute_positioning_shard:
    output:
        shard_result("accumulation", "fig17"),
    params:
        zone=ACCUMULATION["zone"],
        positioning=POSITIONING,
    log:
        log_file("accumulation", "shards/fig17_{shard}"),
    benchmark:
        benchmark_file("accumulation", "shards/fig17_{shard}")
    conda:
        ENV
    script:
        "../scripts/compute_positioning_shard.py"


rule gather_positioning:
    input:
        shard_results("accumulation", "fig17", POSITIONING["shards"]),
    output:
        results("accumulation", "fig17"),
    params:
        positioning=POSITIONING,
    log:
        log_file("accumulation", "fig17"),
    conda:
        ENV
    script:
        "../scripts/gather_positioning.py"


rule compute_portraits:
    output:
        results("accumulation", "fig16"),
    params:
        zone=ACCUMULATION["zone"],
        setting={k: POSITIONING[k] for k in ("dt", "dy")},
        portraits=ACCUMULATION["portraits"],
    log:
        log_file("accumulation", "fig16"),
    conda:
        ENV
    script:
        "../scripts/compute_portraits.py"


rule compute_stick_map:
    output:
        results("accumulation", "fig18"),
    params:
        zone=ACCUMULATION["zone"],
        stick_map=ACCUMULATION["stick_map"],
    log:
        log_file("accumulation", "fig18"),
    conda:
        ENV
    script:
        "../scripts/compute_stick_map.py"


TARGETS.extend(results("accumulation", name) for name in ("fig16", "fig17", "fig18"))
