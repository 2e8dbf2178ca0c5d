# Stage "simulation": each scene simulated with its own solver block into
# results/simulation/<scene>.h5, a rerun recording for scenes that ask for one, and
# Figs. 3, 9 and 12 drawn from the results.


rule simulate_scene:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("simulation", "{scene}"),
    log:
        log_file("simulation", "{scene}"),
    benchmark:
        "results/benchmarks/simulation/{scene}.tsv"
    script:
        "../scripts/simulate_scene.py"


rule record_rerun:
    input:
        results("simulation", "{scene}"),
    output:
        results("rerun", "{scene}", "rrd"),
    log:
        log_file("rerun", "{scene}"),
    script:
        "../scripts/record_rerun.py"


rule plot_fig03:
    input:
        results("simulation", config["figures"]["fig03"]["scene"]),
    output:
        figure("fig03"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig03"),
    script:
        "../scripts/plot_fig03.py"


rule plot_fig09:
    input:
        [results("simulation", name) for name in config["figures"]["fig09"]["scenes"]],
    output:
        figure("fig09"),
    params:
        dpi=config["figures"]["dpi"],
        periods=config["figures"]["fig09"]["periods"],
    log:
        log_file("figures", "fig09"),
    script:
        "../scripts/plot_fig09.py"


rule plot_fig12:
    input:
        results("simulation", config["figures"]["fig12"]["scene"]),
    output:
        figure("fig12"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig12"),
    script:
        "../scripts/plot_fig12.py"


TARGETS.extend(results("simulation", name) for name in scenes("simulation"))
TARGETS.extend(results("rerun", name, "rrd") for name in scenes("simulation") if SCENES[name].record.rerun)
TARGETS.extend(figure(name) for name in ("fig03", "fig09", "fig12"))
