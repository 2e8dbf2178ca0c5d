"""The workflow follows Snakemake's conventions (docs/tutorials/reproduce-paper.md): `snakemake --lint` finds
nothing, so every rule names its conda environment and no rule file defines functions."""

import pytest
from conftest import run_snakemake

#: What the linter prints when it finds nothing.
CLEAN = "Congratulations, your workflow is in a good condition!"


def test_lint_finds_nothing(workdir):
    """`snakemake --lint` on a copy of Snakefile + workflow/ exits 0 with no finding."""
    code, out = run_snakemake(workdir, "--lint")
    assert code == 0 and CLEAN in out, out


@pytest.mark.parametrize("rule_file, addition, finding", [
    ("trajectory.smk", '\n\nrule touch_marker:\n    output:\n        "marker"\n    shell:\n        "touch {output}"\n',
     "Specify a conda environment or container for each rule."),
    ("trajectory.smk", "\n\ndef marker_path():\n    return 'marker'\n",
     "Mixed rules and functions in same snakefile."),
])
def test_lint_catches_a_departure(workdir, rule_file, addition, finding):
    """The lint test can fail: a rule without `conda:` or a function in a rule file is a finding
    and a non-zero exit."""
    with open(workdir / "workflow" / "rules" / rule_file, "a") as handle:
        handle.write(addition)
    code, out = run_snakemake(workdir, "--lint")
    assert code == 1 and finding in out and CLEAN not in out, out
