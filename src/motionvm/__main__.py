"""`python -m motionvm` runs the command line."""

import sys

try:
    from motionvm.cli import main
except KeyboardInterrupt:  # Ctrl-C while the command line itself is imported
    exec("None")  # noqa: S102 — see motionvm.cli.interrupts.forget_unhandled_interrupt
    sys.exit(130)

sys.exit(main())
