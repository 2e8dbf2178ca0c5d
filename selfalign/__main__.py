"""``python -m selfalign``: the command line (:mod:`selfalign.cli`)."""

from selfalign.cli import main

main()
