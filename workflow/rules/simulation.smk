# Stage "simulation": each scene simulated with its own solver block into
# results/simulation/<scene>.h5, and a rerun recording for scenes that ask for one.


rule simulate_scene:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("simulation", "{scene}"),
    log:
        log_file("simulation", "{scene}"),
    benchmark:
        benchmark_file("simulation", "{scene}")
    conda:
        ENV
    script:
        "../scripts/simulate_scene.py"


rule record_rerun:
    input:
        results("simulation", "{scene}"),
    output:
        results("rerun", "{scene}", "rrd"),
    log:
        log_file("rerun", "{scene}"),
    conda:
        ENV
    script:
        "../scripts/record_rerun.py"


TARGETS.extend(results("simulation", name) for name in scenes("simulation"))
TARGETS.extend(results("rerun", name, "rrd") for name in scenes("simulation") if SCENES[name].record.rerun)
