"""Deprecated: moved to adaptive_cpca.torch.model (this path goes in the next version)."""
from ._moved import moved

moved(__name__, "adaptive_cpca.torch.model")
