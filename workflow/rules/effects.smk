# Stage "effects": what the friction laws beyond the paper (issue 16) do to stopping and
# accumulation, at the accumulation stage's zone and Fig. 17's dt, dy.  Its figure is a rule
# of figures.smk (plot_static_friction).

EFFECTS = config["stages"]["effects"]


rule compute_static_friction:
    output:
        results("effects", "static_friction"),
    params:
        zone=ACCUMULATION["zone"],
        setting={k: POSITIONING[k] for k in ("dt", "dy")},
        study=EFFECTS["static_friction"],
    log:
        log_file("effects", "static_friction"),
    benchmark:
        benchmark_file("effects", "static_friction")
    conda:
        ENV
    script:
        "../scripts/compute_static_friction.py"


TARGETS.append(results("effects", "static_friction"))
