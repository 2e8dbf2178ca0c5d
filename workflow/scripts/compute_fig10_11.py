"""Figs. 10, 11: one shard of a (y2'', y3'') map, the gathered map results/classification/<map>.h5,
or the verification of both maps against simulation (verify_fig10_11)."""

from pathlib import Path

import numpy as np

from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.stages.classification import gather_map, map_shard, map_verification
from selfalign.stages.common import logged, shard_rows

with logged(snakemake.log[0]) as log:
    if snakemake.rule == "verify_fig10_11":
        attrs = {}
        for path in snakemake.input:
            result = read_h5(path)
            name = Path(path).stem
            check = map_verification(result["datasets"], result["attrs"])
            attrs.update({f"{name}_{k}": v for k, v in check.items()})
            log.info("%s: %s", name, check)
        write_h5(snakemake.output[0], {}, attrs)
        failed = [k for k, v in attrs.items() if k.endswith("_passed") and not v]
        if failed:
            raise RuntimeError(f"closed-form and simulated vbar disagree beyond the target: {failed}")
    else:
        m = snakemake.params.map
        y2, y3 = (np.linspace(m[k]["from"], m[k]["to"], m[k]["count"]) for k in ("y2", "y3"))
        if snakemake.rule == "compute_map_shard":
            index = int(snakemake.wildcards.shard)
            rows = shard_rows(y2.size, snakemake.params.shards, index)
            datasets = map_shard(m["dt"], m["dy"], y2, y3, rows)
            write_h5(snakemake.output[0], datasets, {"row_start": rows.start, "row_stop": rows.stop})
            log.info("shard %d: rows %d:%d of %d", index, rows.start, rows.stop, y2.size)
        else:
            shards = [read_h5(path)["datasets"] for path in snakemake.input]
            datasets, attrs = gather_map(m["dt"], m["dy"], y2, y3, shards)
            write_h5(snakemake.output[0], datasets, attrs)
            log.info("%s: %d x %d map from %d shards, cases %s", snakemake.wildcards.map, y2.size, y3.size,
                     len(shards), sorted(set(np.unique(datasets["case"]).tolist())))
