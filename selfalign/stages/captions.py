"""The captions of the figures, rendered once for every place that shows them.

Each figure's caption is a reStructuredText template, ``workflow/report/<caption>.rst``, that
Snakemake's report renders with the job's ``snakemake`` object (``snakemake.config[...]``,
``snakemake.params.options``).  :func:`render_caption` renders it the same way outside the
report, and :func:`figure_index` writes ``figures/README.md``: every figure with its files and
its caption, so that someone browsing ``figures/`` reads what each figure shows; the
documentation's gallery is made from that index.
"""

from __future__ import annotations

from types import SimpleNamespace

#: The heading of the figure index; the gallery replaces it by its own.
INDEX_TITLE = "# Figures"
#: The line that opens the entry of a figure in the index: "## <name>".
ENTRY_PREFIX = "## "


def render_caption(template: str, config: dict, options: dict | None = None) -> str:
    """The caption ``template`` rendered as Snakemake's report renders it.

    Parameters
    ----------
    template : str
        A caption, reStructuredText with Jinja2 expressions such as
        ``{{ snakemake.config["figures"]["dpi"] }}`` or ``{{ snakemake.params.options.f_max }}``.
    config : dict
        The workflow's configuration.
    options : dict, optional
        The options the figure is drawn with (``snakemake.params.options`` of its plot rule).

    Returns
    -------
    str
        The caption with every expression replaced by its value.

    Raises
    ------
    jinja2.UndefinedError
        If the caption names a value the configuration or the options lack.

    Examples
    --------
    >>> render_caption("f clipped at {{ snakemake.params.options.f_max }}", {}, {"f_max": 0.8})
    'f clipped at 0.8'
    """
    import jinja2

    snakemake = SimpleNamespace(config=config, params=SimpleNamespace(options=options or {}))
    environment = jinja2.Environment(undefined=jinja2.StrictUndefined, keep_trailing_newline=False)
    return environment.from_string(template).render(snakemake=snakemake).strip()


def figure_index(figures: list[dict], formats: list[str]) -> str:
    """The Markdown of ``figures/README.md``: every figure, its files and its caption.

    Parameters
    ----------
    figures : list of dict
        One per figure, in the order listed: ``name`` (the stem of ``figures/<name>.<format>``),
        ``category`` (its group in the report) and ``caption`` (rendered, :func:`render_caption`).
    formats : list of str
        The file formats every figure is written in; the first is shown inline.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        If a figure is listed twice or has an empty caption.

    Examples
    --------
    >>> text = figure_index([{"name": "fig07", "category": "Simulation", "caption": "The profile."}],
    ...                     ["png", "pdf"])
    >>> print(text[text.index("## fig07"):].strip())
    ## fig07
    <BLANKLINE>
    Simulation · [png](fig07.png) · [pdf](fig07.pdf)
    <BLANKLINE>
    ![fig07](fig07.png)
    <BLANKLINE>
    The profile.
    """
    names = [f["name"] for f in figures]
    if len(set(names)) != len(names):
        raise ValueError(f"figures listed twice in the index: {sorted({n for n in names if names.count(n) > 1})}")
    lines = [INDEX_TITLE, "",
             "Every figure the workflow draws (`snakemake -c2`), with its caption; this file is written by the "
             "workflow's rule `write_figure_index`. Figures named `figNN` are the paper's; the others go beyond "
             "it. Every figure is drawn at print size for a journal page (84 or 174 mm wide, text of 7 pt and "
             f"more) and written as {' and '.join(fmt.upper() for fmt in formats)}."]
    for f in figures:
        if not f["caption"].strip():
            raise ValueError(f"figure {f['name']!r} has an empty caption")
        files = " · ".join(f"[{fmt}]({f['name']}.{fmt})" for fmt in formats)
        lines += ["", f"{ENTRY_PREFIX}{f['name']}", "", f"{f['category']} · {files}", "",
                  f"![{f['name']}]({f['name']}.{formats[0]})", "", f["caption"].strip()]
    return "\n".join(lines) + "\n"
