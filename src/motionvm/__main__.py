"""`python -m motionvm` runs the command line."""

import sys

from motionvm.cli import main

sys.exit(main())
