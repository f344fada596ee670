"""The import paths from before the package took its layout (torch_lighting,
torch_model, torch_domain, torch_dataset, image_reading), kept
for one version: each old module is a stand-in that warns and puts the
module it moved to in its place, so that its names (and monkeypatching
them) reach the one module."""

import importlib
import sys
import warnings


def moved(old, new):
    """Replaces module `old` with `new`, with a DeprecationWarning."""
    warnings.warn(f"{old} is deprecated and goes in the next version: import {new}",
                  DeprecationWarning, stacklevel=3)
    sys.modules[old] = importlib.import_module(new)
