# Stage "optimal_motion" (docs/explanation/fig6-revisited.md): Fig. 6 of the paper (Sect. 4.4.2)
# revisited.  At Fig. 6's limits the paper's optimum, the Fourier SQP of each order, the best
# three-phase profile and the fastest table motion side by side, and two sweeps of the limits,
# computed into one result file; the figure fig06_revisited is drawn from it by a separate rule
# (this file is included after figures.smk, whose formats, dpi and report categories it uses).

OPTIMAL_MOTION = config["stages"]["optimal_motion"]


rule compare_optimal_motion:
    output:
        results("optimal_motion", "fig06_revisited"),
    params:
        settings=OPTIMAL_MOTION,
    log:
        log_file("optimal_motion", "fig06_revisited"),
    benchmark:
        benchmark_file("optimal_motion", "fig06_revisited")
    conda:
        ENV
    script:
        "../scripts/compare_optimal_motion.py"


rule plot_fig06_revisited:
    input:
        results("optimal_motion", "fig06_revisited"),
    output:
        captioned_figure("fig06_revisited", STEADY_STATE_FIGURES),
        *(figure("fig06_revisited", fmt) for fmt in FIGURE_FORMATS[1:]),
    params:
        dpi=FIGURE_CONFIG["dpi"],
    log:
        log_file("figures", "fig06_revisited"),
    conda:
        ENV
    script:
        "../scripts/plot_fig06_revisited.py"


TARGETS.append(results("optimal_motion", "fig06_revisited"))
TARGETS.extend(figure("fig06_revisited", fmt) for fmt in FIGURE_FORMATS)
