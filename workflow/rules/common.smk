# Helpers shared by every stage: scene lookup, result paths, the list of final targets.
# Every scene the config names is loaded and validated here, when the workflow is
# parsed, so a bad scene file stops the run before any job starts.

import re
from pathlib import Path

from snakemake.exceptions import WorkflowError

import selfalign

#: Final outputs of all stages; each stage's .smk extends it, rule `all` requests it.
TARGETS = []

#: Conda environment of every job (`snakemake --use-conda`): the package with its workflow extra, pinned.
ENV = "../envs/selfalign.yaml"


def scenes(stage):
    """Scene names the config lists for `stage` (none for the stages that build their own profiles)."""
    return list(config["stages"][stage].get("scenes", []))


def scene_file(name):
    return f"{config['scenes_dir']}/{name}.yaml"


def results(stage, name, ext="h5"):
    """Path of a result file: results/<stage>/<name>.<ext>."""
    return f"results/{stage}/{name}.{ext}"


def shard_result(stage, name, shard="{shard}"):
    """Path of one shard of a sharded sweep: results/<stage>/shards/<name>_<shard>.h5 (a row
    block of the sweep's first axis, `selfalign.stages.common.shard_rows`)."""
    return results(stage, f"shards/{name}_{shard}")


def shard_results(stage, name, shards):
    """The `shards` shard paths of `name`, in row order: the inputs of its gather rule."""
    return [shard_result(stage, name, i) for i in range(shards)]


def log_file(stage, name):
    return f"results/logs/{stage}/{name}.log"


def benchmark_file(stage, name):
    """Snakemake's timing of a job: results/benchmarks/<stage>/<name>.tsv."""
    return f"results/benchmarks/{stage}/{name}.tsv"


def figure(name, fmt="png"):
    """Path of a figure file: figures/<name>.<fmt>."""
    return f"figures/{name}.{fmt}"


#: Every figure with a caption, for the figure index figures/README.md (written by write_figure_index):
#: name -> (caption file stem, report category, options of its drawing).
FIGURE_CAPTIONS = {}


def captioned_figure(name, category, caption=None, options=None):
    """figures/<name>.<first format> as a report output with its caption,
    workflow/report/<caption or name>.rst, registered for the figure index."""
    stem = caption or name
    FIGURE_CAPTIONS[name] = (stem, category, options or {})
    return report(figure(name, config["figures"]["formats"][0]), caption=f"../report/{stem}.rst", category=category)


def _load_scenes():
    """Every scene named in the config, validated; a SceneError becomes a WorkflowError."""
    names = {n for stage in config["stages"] for n in scenes(stage)}
    names |= {f["scene"] for f in config["figures"].values() if isinstance(f, dict) and "scene" in f}
    loaded = {}
    for name in sorted(names):
        path = scene_file(name)
        try:
            scene = selfalign.load_scene(path)
        except selfalign.SceneError as exc:
            raise WorkflowError(f"invalid scene: {exc}") from None
        if scene.name != name:
            raise WorkflowError(f"invalid scene: {path}: name: {scene.name!r} differs from the "
                                f"file name {name!r}; drop the key or rename the file")
        loaded[name] = scene
    return loaded


#: name -> validated selfalign.Scene
SCENES = _load_scenes()

wildcard_constraints:
    scene="|".join(re.escape(n) for n in sorted(SCENES)),
    shard=r"\d+",
