"""How colours look to readers with a colour-vision deficiency, and how far apart they stay.

A colour is simulated for protanopia, deuteranopia and tritanopia with the matrices of
Machado, Oliveira and Fernandes (2009, severity 1), which act on linear RGB; two colours are
compared by the CIE76 colour difference Delta E (Euclidean distance in CIELAB, D65 white).
Below about 10 two colours are hard to tell apart; the figure standard
(:mod:`selfalign.plots.style`) keeps every two case colours at least :data:`MIN_DELTA_E` apart
for every reader.
"""

from __future__ import annotations

import itertools

import numpy as np

#: Colour difference every two categorical colours keep, for every kind of colour vision.
MIN_DELTA_E = 15.0
#: Machado et al. (2009) simulation matrices at severity 1, on linear RGB; "normal" is the identity.
DEFICIENCIES = {
    "normal": np.eye(3),
    "protanopia": np.array([[0.152286, 1.052583, -0.204868],
                            [0.114503, 0.786281, 0.099216],
                            [-0.003882, -0.048116, 1.051998]]),
    "deuteranopia": np.array([[0.367322, 0.860646, -0.227968],
                              [0.280085, 0.672501, 0.047413],
                              [-0.011820, 0.042940, 0.968881]]),
    "tritanopia": np.array([[1.255528, -0.076749, -0.178779],
                            [-0.078411, 0.930809, 0.147602],
                            [0.004733, 0.691367, 0.303900]]),
}
#: sRGB (linear) to CIE XYZ, and the D65 white point.
_RGB_TO_XYZ = np.array([[0.4124564, 0.3575761, 0.1804375],
                        [0.2126729, 0.7151522, 0.0721750],
                        [0.0193339, 0.1191920, 0.9503041]])
_WHITE = np.array([0.95047, 1.0, 1.08883])


def _linear(rgb):
    rgb = np.asarray(rgb, dtype=float)
    return np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)


def lab(color, vision: str = "normal") -> np.ndarray:
    """CIELAB (L*, a*, b*) of the matplotlib colour ``color`` as a reader with ``vision`` sees it.

    Parameters
    ----------
    color : matplotlib colour
        E.g. ``"#0072B2"``, ``"0.6"`` or an RGB tuple.
    vision : str
        A key of :data:`DEFICIENCIES`.

    Returns
    -------
    numpy.ndarray
        (L*, a*, b*).

    Raises
    ------
    ValueError
        If ``vision`` is not a key of :data:`DEFICIENCIES`.

    Examples
    --------
    >>> [round(float(v), 2) for v in lab("red")]  # the textbook values of sRGB red
    [53.24, 80.09, 67.2]
    """
    from matplotlib.colors import to_rgb

    if vision not in DEFICIENCIES:
        raise ValueError(f"colour vision {vision!r} is not one of {', '.join(DEFICIENCIES)}")
    xyz = _RGB_TO_XYZ @ np.clip(DEFICIENCIES[vision] @ _linear(to_rgb(color)), 0.0, 1.0)
    t = xyz / _WHITE
    f = np.where(t > (6 / 29) ** 3, np.cbrt(t), t / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def delta_e(a, b, vision: str = "normal") -> float:
    """CIE76 colour difference of the colours ``a`` and ``b`` for a reader with ``vision``.

    Parameters
    ----------
    a, b : matplotlib colour
    vision : str
        A key of :data:`DEFICIENCIES`.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If ``vision`` is not a key of :data:`DEFICIENCIES`.

    Examples
    --------
    >>> round(delta_e("tab:green", "tab:red", "deuteranopia"), 1)
    7.3
    """
    return float(np.linalg.norm(lab(a, vision) - lab(b, vision)))


def closest_pair(colors: dict) -> tuple[float, str, object, object]:
    """The two colours of ``colors`` (name -> colour) that come closest for any reader.

    Parameters
    ----------
    colors : dict
        At least two named colours.

    Returns
    -------
    tuple
        (Delta E, vision, name, name) of the closest pair.

    Raises
    ------
    ValueError
        If fewer than two colours are given.

    Examples
    --------
    >>> d, vision, a, b = closest_pair({"green": "tab:green", "red": "tab:red", "blue": "tab:blue"})
    >>> round(d, 1), vision, a, b
    (7.3, 'deuteranopia', 'green', 'red')
    """
    if len(colors) < 2:
        raise ValueError(f"closest_pair needs at least two colours, got {len(colors)}")
    return min((delta_e(colors[a], colors[b], vision), vision, a, b)
               for vision in DEFICIENCIES for a, b in itertools.combinations(colors, 2))
