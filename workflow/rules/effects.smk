# Stage "effects": what the friction laws beyond the paper do to stopping and
# accumulation, at the accumulation stage's zone and Fig. 17's dt, dy: static friction and the
# Stribeck law (which also gives vbar on Fig. 11's plane).  Its figures are rules of figures.smk
# (plot_static_friction, plot_stribeck_friction).

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


rule compute_stribeck:
    output:
        results("effects", "stribeck"),
    params:
        zone=ACCUMULATION["zone"],
        setting={k: POSITIONING[k] for k in ("dt", "dy")},
        study=EFFECTS["stribeck"],
    log:
        log_file("effects", "stribeck"),
    benchmark:
        benchmark_file("effects", "stribeck")
    conda:
        ENV
    script:
        "../scripts/compute_stribeck.py"


TARGETS.append(results("effects", "stribeck"))
