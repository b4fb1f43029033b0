"""The calibration of the shipped skis, cited by their provenance: now ``skisnow calibrate``."""

import sys

from skisnow.cli import main

sys.exit(main(["calibrate", *sys.argv[1:]]))
