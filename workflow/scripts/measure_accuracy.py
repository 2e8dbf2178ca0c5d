"""Work-precision study of a scene into results/accuracy/<scene>.h5."""

from selfalign import load_scene
from selfalign.analysis.accuracy import StudySettings, study
from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    scene = load_scene(snakemake.input.scene)
    datasets, attrs, groups = study(scene, StudySettings.from_config(snakemake.params.settings))
    write_h5(snakemake.output[0], datasets, attrs, groups)
    ivp = (f"ivp max err/rtol {attrs['ivp_max_err_over_rtol']:.3g}" if "ivp_max_err_over_rtol" in attrs
           else attrs["ivp_not_run"])
    log.info("%s (%d part(s)): Moreau order %.3f, speed ratio exact/Moreau at error %g: %.3g (%s), "
             "%s, exact %.3g events/s; written to %s", scene.name, attrs["parts"], attrs["moreau_order"],
             attrs["target_error"], datasets["speed_ratio_at_target"],
             "interpolated" if attrs["target_interpolated"] else "extrapolated",
             ivp, datasets["exact_events_per_second"], snakemake.output[0])
