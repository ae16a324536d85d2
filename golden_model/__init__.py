# SPDX-License-Identifier: MIT
"""Bit-exact golden model of the ORB feature-extraction accelerator."""

from .config import Config, ConfigError
from .features import Features, first_difference, read_csv, write_csv
from .pipeline import extract

__all__ = ["Config", "ConfigError", "Features", "extract", "first_difference", "read_csv", "write_csv"]
__version__ = "0.1.0"
