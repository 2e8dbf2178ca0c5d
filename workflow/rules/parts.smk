# Stage "parts" (docs/explanation/queue.md): a queue of parts at the stop zone (the paper's Sect. 8,
# recommendation 5, on the zone of Sect. 7).  One rule computes the study on the Fig. 18 setting and the
# SI queue on the design the design stage chose for a spec (its result file is the input), one draws the
# figures, one records the queue as boxes for rerun.  This file is included after figures.smk and
# design.smk, whose formats, dpi and result paths it uses.

PARTS = config["stages"]["parts"]
PARTS_FIGURES = "Several parts: a queue at the stop zone (Sect. 8)"


rule compute_queue:
    input:
        results("design", PARTS["design"]["spec"]),
    output:
        results("parts", "queue"),
    params:
        settings=PARTS,
        zone=ACCUMULATION["zone"],
    log:
        log_file("parts", "queue"),
    benchmark:
        benchmark_file("parts", "queue")
    conda:
        ENV
    script:
        "../scripts/compute_queue.py"


rule plot_queue:
    input:
        results("parts", "queue"),
    output:
        captioned_figure("parts_queue", PARTS_FIGURES),
        captioned_figure("parts_motion", PARTS_FIGURES),
        *(figure(name, fmt) for name in ("parts_queue", "parts_motion") for fmt in FIGURE_FORMATS[1:]),
    params:
        dpi=FIGURE_CONFIG["dpi"],
    log:
        log_file("figures", "parts_queue"),
    conda:
        ENV
    script:
        "../scripts/plot_queue.py"


rule record_queue:
    input:
        results("parts", "queue"),
    output:
        results("rerun", "parts_queue", "rrd"),
    log:
        log_file("parts", "record_queue"),
    conda:
        ENV
    script:
        "../scripts/record_queue.py"


TARGETS.append(results("parts", "queue"))
TARGETS.append(results("rerun", "parts_queue", "rrd"))
TARGETS.extend(figure(name, fmt) for name in ("parts_queue", "parts_motion") for fmt in FIGURE_FORMATS)
