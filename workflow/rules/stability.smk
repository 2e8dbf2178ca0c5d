# Stage "stability" (Sect. 6.1): Floquet multipliers of each scene's steady state by the
# three methods of selfalign.floquet, and over (y2'', y3'') grids of three-phase profiles.


rule compute_stability:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("stability", "{scene}"),
    params:
        moreau_steps=config["stages"]["stability"]["moreau_steps"],
        moreau_eps=config["stages"]["stability"]["moreau_eps"],
    log:
        log_file("stability", "{scene}"),
    script:
        "../scripts/compute_stability.py"


rule compute_stability_grid:
    output:
        results("stability", "grid_{grid}"),
    params:
        grid=lambda wildcards: config["stages"]["stability"]["grids"][wildcards.grid],
        moreau_steps=config["stages"]["stability"]["grid_moreau_steps"],
    wildcard_constraints:
        grid="|".join(re.escape(g) for g in sorted(config["stages"]["stability"]["grids"])),
    log:
        log_file("stability", "grid_{grid}"),
    script:
        "../scripts/compute_stability.py"


TARGETS.extend(results("stability", name) for name in scenes("stability"))
TARGETS.extend(results("stability", f"grid_{g}") for g in config["stages"]["stability"]["grids"])
