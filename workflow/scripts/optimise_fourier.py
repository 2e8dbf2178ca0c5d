"""Fig. 6: Fourier shape optimisation (Sect. 4.4.2) into results/classification/fig06.h5."""

from selfalign.io.hdf5 import write_h5
from selfalign.stages.classification import fig06_results
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    p = snakemake.params.fourier
    datasets, attrs, opt = fig06_results(p["dt"], p["dy"], p["yd_max"], p["ydd_max"], order=p["order"],
                                         max_iter=p["max_iter"])
    write_h5(snakemake.output[0], datasets, attrs, config=dict(snakemake.params.items()))
    log.info("SQP: %s after %d iterations, %d steady states, %.1f s; f = %.4g (start %.4g, best three-phase "
             "%.4g); written to %s", opt.message, opt.iterations, opt.evaluations, opt.seconds, opt.f,
             attrs["start_f"], attrs["three_phase_f"], snakemake.output[0])
