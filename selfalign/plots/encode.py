"""A drawn figure encoded as the bytes of an image file (PNG, PDF or SVG), reproducibly: no
software version or date in the metadata and constant SVG ids, so the same drawing gives the
same bytes.  PDF files embed their fonts as TrueType (Type 42), which journals accept and
editors can change, rather than as Type 3 drawings.  Writing the file is the caller's
(:func:`selfalign.stages.common.save_figure`).
"""

from __future__ import annotations

import io

#: Figure formats -> metadata left out (software version, dates).
FIGURE_METADATA = {
    "png": {"Software": None},
    "pdf": {"Creator": None, "Producer": None, "CreationDate": None},
    "svg": {"Creator": None, "Date": None},
}


def figure_bytes(fig, fmt: str, dpi: int) -> bytes:
    """``fig`` as a ``fmt`` file (a key of FIGURE_METADATA); ``dpi`` sets the resolution of PNG
    and of raster parts of the vector formats."""
    from matplotlib import rc_context

    if fmt not in FIGURE_METADATA:
        raise ValueError(f"figure format {fmt!r} is not one of {', '.join(FIGURE_METADATA)}")
    buffer = io.BytesIO()
    with rc_context({"svg.hashsalt": "selfalign", "pdf.fonttype": 42}):
        fig.savefig(buffer, format=fmt, dpi=dpi, metadata=FIGURE_METADATA[fmt])
    return buffer.getvalue()
