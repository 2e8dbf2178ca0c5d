# The figures: one rule plot_<name> per figure, all made from the one definition below.
# Each draws figures/<name>.<format> for every format of `figures.formats` from its result
# files with selfalign.stages.figures.draw (computing and plotting stay in separate rules, so
# restyling never reruns a simulation); the first format carries the caption,
# workflow/report/<name>.rst, into `snakemake --report`.

from selfalign.stages.figures import accuracy_figure

FIGURE_CONFIG = config["figures"]
FIGURE_FORMATS = FIGURE_CONFIG["formats"]
SIMULATION_FIGURES = "Simulation (Sects. 2-5)"
STEADY_STATE_FIGURES = "Steady state and classification (Sects. 4-5)"
STABILITY_FIGURES = "Stability and convergence (Sect. 6)"
ACCUMULATION_FIGURES = "Stopping and accumulation (Sect. 7)"
SOLVER_FIGURES = "Solvers: accuracy against cost"
DESIGN_FIGURES = "Designing a self-aligning station"
EFFECT_FIGURES = "Beyond the paper's model: finite jerk and friction laws"
PORTRAITS = ACCUMULATION["portraits"]["settings"]

#: The work-precision figures, one per family of accuracy scenes (selfalign.stages.figures.accuracy_figure:
#: the paper's model, effects beyond it, several parts, planar motion) -> their scenes, in the config's order.
ACCURACY_FIGURES = {}
for _name in scenes("accuracy"):
    ACCURACY_FIGURES.setdefault(accuracy_figure(SCENES[_name]), []).append(_name)

#: name -> (report category, input result files, options of selfalign.stages.figures.draw)
FIGURES = {
    # The stop zone of Sect. 3.3 (Fig. 2), drawn from the model's friction coefficient itself (no
    # result file) with the accumulation stage's zone; after changing the model: --forcerun plot_fig02.
    "fig02": (SIMULATION_FIGURES, [], {"zone": ACCUMULATION["zone"]}),
    "fig03": (SIMULATION_FIGURES, [results("simulation", FIGURE_CONFIG["fig03"]["scene"])], {}),
    "fig04": (STEADY_STATE_FIGURES, [results("classification", "fig04")], {}),
    "fig05": (STEADY_STATE_FIGURES, [results("classification", "fig05")], {}),
    "fig06": (STEADY_STATE_FIGURES, [results("classification", "fig06")], {}),
    "fig07": (SIMULATION_FIGURES, [results("trajectory", FIGURE_CONFIG["fig07"]["scene"])], {}),
    # Drawn from the decision tree in selfalign/analysis/classification.py itself (no result
    # file); after changing the tree: snakemake -c2 --forcerun plot_fig08.
    "fig08": (STEADY_STATE_FIGURES, [], {}),
    "fig09": (SIMULATION_FIGURES, [results("simulation", n) for n in FIGURE_CONFIG["fig09"]["scenes"]],
              {"periods": FIGURE_CONFIG["fig09"]["periods"]}),
    "fig10": (STEADY_STATE_FIGURES, [results("classification", "fig10")], {"f_max": FIGURE_CONFIG["fig10"]["f_max"]}),
    "fig11": (STEADY_STATE_FIGURES, [results("classification", "fig11")], {"f_max": FIGURE_CONFIG["fig11"]["f_max"]}),
    "fig12": (SIMULATION_FIGURES, [results("simulation", FIGURE_CONFIG["fig12"]["scene"])], {}),
    "fig13": (STABILITY_FIGURES, [results("convergence", FIGURE_CONFIG["fig13"]["scene"])], {}),
    "floquet_fig17": (STABILITY_FIGURES, [results("stability", "grid_fig17")], {}),
    "fig14": (ACCUMULATION_FIGURES, [results("accumulation", "fig16")], {"setting": PORTRAITS[-1]}),
    "fig15": (ACCUMULATION_FIGURES, [results("accumulation", "fig16")], {"setting": PORTRAITS[-1]}),
    "fig16": (ACCUMULATION_FIGURES, [results("accumulation", "fig16")], {"settings": PORTRAITS}),
    # Fig. 17 marks the setting of Fig. 18, read from its result.
    "fig17": (ACCUMULATION_FIGURES, [results("accumulation", "fig17"), results("accumulation", "fig18")], {}),
    "fig18": (ACCUMULATION_FIGURES, [results("accumulation", "fig18")], {}),
    **{name: (SOLVER_FIGURES, [results("accuracy", n) for n in names], {})
       for name, names in ACCURACY_FIGURES.items()},
    "static_friction": (EFFECT_FIGURES, [results("effects", "static_friction")], {}),
    "stribeck_friction": (EFFECT_FIGURES, [results("effects", "stribeck")], {}),
    # The finite-jerk study: the steady planes, and the stopping over Fig. 17's plane.
    "finite_jerk": (EFFECT_FIGURES, [results("finite_jerk", "finite_jerk")], {}),
    "finite_jerk_stopping": (EFFECT_FIGURES, [results("finite_jerk", "finite_jerk")], {}),
    # One per design spec (selfalign.stages.figures.FAMILIES), all with the caption design.rst.
    **{f"design_{name}": (DESIGN_FIGURES, [results("design", name)], {}) for name in DESIGNS},
}
#: Figures that share a caption: name -> caption file stem (default: the name).
CAPTIONS = {f"design_{name}": "design" for name in DESIGNS}


for name, (category, inputs, options) in FIGURES.items():

    rule:
        name:
            f"plot_{name}"
        input:
            inputs,
        output:
            captioned_figure(name, category, CAPTIONS.get(name), options),
            *(figure(name, fmt) for fmt in FIGURE_FORMATS[1:]),
        params:
            figure=name,
            options=options,
            dpi=FIGURE_CONFIG["dpi"],
        log:
            log_file("figures", name),
        conda:
            ENV
        script:
            "../scripts/plot_figure.py"


TARGETS.extend(figure(name, fmt) for name in FIGURES for fmt in FIGURE_FORMATS)
