"""plots layer: figure functions, drawn with matplotlib (the `plots` extra)."""

from ..model.errors import require_extra

require_extra("matplotlib", "plots", "selfalign.plots")
