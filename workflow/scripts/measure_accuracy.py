"""Work-precision study of a scene into results/accuracy/<scene>.h5."""

from selfalign import load_scene
from selfalign.analysis.accuracy import StudySettings, study
from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    scene = load_scene(snakemake.input.scene)
    datasets, attrs, groups = study(scene, StudySettings.from_config(snakemake.params.settings))
    write_h5(snakemake.output[0], datasets, attrs, groups)
    log.info("%s: Moreau order %.3f, speed ratio exact/Moreau at error %g: %.3g (%s), "
             "ivp max err/rtol %.3g, exact %.3g events/s; written to %s", scene.name, attrs["moreau_order"],
             attrs["target_error"], datasets["speed_ratio_at_target"],
             "interpolated" if attrs["target_interpolated"] else "extrapolated",
             attrs["ivp_max_err_over_rtol"], datasets["exact_events_per_second"], snakemake.output[0])
