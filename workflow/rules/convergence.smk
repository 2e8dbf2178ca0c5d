# Stage "convergence" (Sect. 6.2): two velocity transients of each scene and the Lyapunov
# function V = (v1 - v2)^2 / 2 with its "=" / "!=" intervals, and a rerun recording of them
# for scenes that set record.rerun.

CONVERGENCE = config["stages"]["convergence"]
_missing = [n for n in scenes("convergence") if n not in CONVERGENCE["v20"]]
if _missing:
    raise WorkflowError(f"stages.convergence.v20: no second initial velocity for scene(s) {_missing}")


rule compute_convergence:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("convergence", "{scene}"),
    params:
        v20=lambda wildcards: CONVERGENCE["v20"][wildcards.scene],
    log:
        log_file("convergence", "{scene}"),
    conda:
        ENV
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
        scene="|".join(re.escape(n) for n in scenes("convergence")),
    log:
        log_file("rerun", "{scene}"),
    conda:
        ENV
    script:
        "../scripts/record_convergence.py"


TARGETS.extend(results("convergence", name) for name in scenes("convergence"))
TARGETS.extend(results("rerun", name, "rrd") for name in scenes("convergence") if SCENES[name].record.rerun)
