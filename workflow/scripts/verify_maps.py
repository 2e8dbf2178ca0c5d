"""Closed-form against simulated vbar on every point of the maps into results/classification/verify_maps.h5;
fails when they disagree beyond the target."""

from pathlib import Path

from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.stages.classification import map_verification
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    attrs = {}
    for path in snakemake.input:
        result = read_h5(path)
        name = Path(path).stem
        check = map_verification(result["datasets"], result["attrs"])
        attrs.update({f"{name}_{k}": v for k, v in check.items()})
        log.info("%s: %s", name, check)
    write_h5(snakemake.output[0], {}, attrs, config={"maps": list(snakemake.input)})
    failed = [k for k, v in attrs.items() if k.endswith("_passed") and not v]
    if failed:
        raise RuntimeError(f"closed-form and simulated vbar disagree beyond the target: {failed}")
