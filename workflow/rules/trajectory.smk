# Stage "trajectory": the table motion y(t) of each scene, sampled (Fig. 7 is drawn from it).


rule sample_trajectory:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("trajectory", "{scene}"),
    log:
        log_file("trajectory", "{scene}"),
    conda:
        ENV
    script:
        "../scripts/sample_trajectory.py"


TARGETS.extend(results("trajectory", name) for name in scenes("trajectory"))
