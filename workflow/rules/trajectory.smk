# Stage "trajectory": the table motion y(t) of each scene, and Fig. 7 drawn from it.


rule generate_trajectory:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("trajectory", "{scene}"),
    log:
        log_file("trajectory", "{scene}"),
    script:
        "../scripts/generate_trajectory.py"


rule plot_fig07:
    input:
        results("trajectory", config["figures"]["fig07"]["scene"]),
    output:
        figure("fig07"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig07"),
    script:
        "../scripts/plot_fig07.py"


TARGETS.extend(results("trajectory", name) for name in scenes("trajectory"))
TARGETS.append(figure("fig07"))
