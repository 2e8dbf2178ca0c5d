# Stage "planar" (docs/explanation/planar-alignment.md): a point part on a table moving in the plane (the
# paper's Sect. 8, recommendation 4).  One rule computes the drift maps, the limits of low and high
# acceleration and the entries onto a strip and a corner; one draws the figures; one records two entries in
# the plane for rerun.  This file is included after figures.smk, whose formats and dpi it uses.

PLANAR = config["stages"]["planar"]
PLANAR_FIGURES = "Planar motion: drift and self-alignment in the plane (Sect. 8)"


rule compute_planar:
    output:
        results("planar", "planar"),
    params:
        settings=PLANAR,
    log:
        log_file("planar", "planar"),
    benchmark:
        benchmark_file("planar", "planar")
    conda:
        ENV
    script:
        "../scripts/compute_planar.py"


rule plot_planar:
    input:
        results("planar", "planar"),
    output:
        captioned_figure("planar_drift", PLANAR_FIGURES),
        captioned_figure("planar_alignment", PLANAR_FIGURES),
        *(figure(name, fmt) for name in ("planar_drift", "planar_alignment") for fmt in FIGURE_FORMATS[1:]),
    params:
        dpi=FIGURE_CONFIG["dpi"],
    log:
        log_file("figures", "planar"),
    conda:
        ENV
    script:
        "../scripts/plot_planar.py"


rule record_planar:
    input:
        results("planar", "planar"),
    output:
        results("rerun", "planar_motion", "rrd"),
    log:
        log_file("planar", "record_planar"),
    conda:
        ENV
    script:
        "../scripts/record_planar.py"


TARGETS.append(results("planar", "planar"))
TARGETS.append(results("rerun", "planar_motion", "rrd"))
TARGETS.extend(figure(name, fmt) for name in ("planar_drift", "planar_alignment") for fmt in FIGURE_FORMATS)
