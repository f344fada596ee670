"""The compiled part, where the pure-Python side may call it.

Where `adaptive_cpca._core` loads, the lattice, the SH means and the
`--env-sample` draws come from it (one implementation, the CLI's); the
pure-Python copies serve machines where it does not load, and tests hold
the two equal.
"""

import sys


def compiled_part(starts_threads=True):
    """adaptive_cpca._core; None where it did not load. A call that may
    start threads gets None in a DataLoader worker too (forked: the thread
    pools of TBB and OpenImageIO do not survive a fork); the lattice, SH
    means and draws start none (starts_threads=False), so a worker's frames
    are the main process's to the bit."""
    from . import _core

    if _core is None or (starts_threads and in_dataloader_worker()):
        return None
    return _core


def in_dataloader_worker():
    """True in a torch DataLoader worker (torch imported, and this process
    one of its workers)."""
    torch = sys.modules.get("torch")
    return torch is not None and torch.utils.data.get_worker_info() is not None
