# Stage "stability" (Sect. 6.1): Floquet multipliers of each scene's steady state by the
# methods of selfalign.analysis.floquet, and over (y2'', y3'') grids of three-phase profiles.

STABILITY = config["stages"]["stability"]


rule compute_stability:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("stability", "{scene}"),
    params:
        moreau_steps=STABILITY["moreau_steps"],
        moreau_eps=STABILITY["moreau_eps"],
    log:
        log_file("stability", "{scene}"),
    conda:
        ENV
    script:
        "../scripts/compute_stability.py"


rule compute_stability_grid:
    output:
        results("stability", "grid_{grid}"),
    params:
        grid=lambda wildcards: STABILITY["grids"][wildcards.grid],
    wildcard_constraints:
        grid="|".join(re.escape(g) for g in sorted(STABILITY["grids"])),
    log:
        log_file("stability", "grid_{grid}"),
    conda:
        ENV
    script:
        "../scripts/compute_stability_grid.py"


TARGETS.extend(results("stability", name) for name in scenes("stability"))
TARGETS.extend(results("stability", f"grid_{g}") for g in STABILITY["grids"])
