# Stage "convergence" (Sect. 6.2): two velocity transients of each scene and the Lyapunov
# function V = (v1 - v2)^2 / 2 with its "=" / "!=" intervals, a rerun recording of them for
# scenes that set record.rerun, and Fig. 13.

CONVERGENCE = scenes("convergence")
_missing = [n for n in CONVERGENCE if n not in config["stages"]["convergence"]["v20"]]
if _missing:
    raise WorkflowError(f"stages.convergence.v20: no second initial velocity for scene(s) {_missing}")


rule compute_convergence:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("convergence", "{scene}"),
    params:
        v20=lambda wildcards: config["stages"]["convergence"]["v20"][wildcards.scene],
    log:
        log_file("convergence", "{scene}"),
    script:
        "../scripts/compute_convergence.py"


# results/rerun/<scene>.rrd is also the simulation stage's recording (rule record_rerun);
# for a convergence scene it is this one: v1, v2 and V.
ruleorder: record_convergence > record_rerun


rule record_convergence:
    input:
        results("convergence", "{scene}"),
    output:
        results("rerun", "{scene}", "rrd"),
    wildcard_constraints:
        scene="|".join(re.escape(n) for n in CONVERGENCE),
    log:
        log_file("rerun", "{scene}"),
    script:
        "../scripts/compute_convergence.py"


rule plot_fig13:
    input:
        results("convergence", config["figures"]["fig13"]["scene"]),
    output:
        figure("fig13"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "fig13"),
    script:
        "../scripts/plot_fig13.py"


TARGETS.extend(results("convergence", name) for name in CONVERGENCE)
TARGETS.extend(results("rerun", name, "rrd") for name in CONVERGENCE if SCENES[name].record.rerun)
TARGETS.append(figure("fig13"))
