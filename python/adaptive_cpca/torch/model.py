"""A model file's clusters on a torch device, and the arithmetic of a relight.

docs/formats.md ("Model file"): row p of cluster c under the projected
lighting V_g^T L is u_p . W_c^T V_g^T L + mean_c . V_g^T L, u_p's i8
coefficients times their basis's scale. The arrays stay at their stored
precision (i8, f16) and are widened span by span in the arithmetic, as CPU
torch 1.13 multiplies neither. A relight is then:

1. every cluster's W_c^T V_g^T L at once: all bases are one [sum n_c, N]
   matrix (compress writes the clusters' bases one after another), times the
   scales;
2. each row's coefficients against its cluster's part of that: per cluster
   a dense product ("clusters", the CPU's fastest), or all rows of a span as
   one sparse [rows, sum n_c] matrix ("sparse": no loop over clusters, for
   GPUs, where a loop of thousands of small products would be launch-bound);
3. the means' term gathered per row.
"""

import warnings

import numpy as np
import torch

__all__ = ["DeviceModel"]

# Stored values widened at once: bounds the float32 copy of a span.
_SPAN_ENTRIES = 1 << 22
# Basis rows widened at once.
_BASIS_ROWS = 4096
KERNELS = ("auto", "clusters", "sparse")


class DeviceModel:
    """The cluster arrays of an open model file (h5py) on a device, rows in
    cluster order."""

    def __init__(self, f, path, device, kernel="auto"):
        if kernel not in KERNELS:
            raise ValueError(f"kernel {kernel!r}: one of {', '.join(KERNELS)}")
        self.device = device
        self.kernel = kernel if kernel != "auto" else (
            "sparse" if device.type == "cuda" else "clusters")
        self.global_bases = f["global_basis"].shape[1]
        self.rows = len(f["cluster_rows"])
        n = self.global_bases
        self.ranks = f["cluster_rank"][:].astype(np.int64)
        self.row_offsets = f["cluster_row_offsets"][:].astype(np.int64)
        self.first_basis = np.concatenate([[0], np.cumsum(self.ranks)])
        self.entry_offsets = np.concatenate(
            [[0], np.cumsum(np.diff(self.row_offsets) * self.ranks)])
        if not (np.array_equal(f["cluster_basis_offsets"][:], self.first_basis * n) and
                np.array_equal(f["coefficient_offsets"][:], self.entry_offsets)):
            raise ValueError(f"{path}: the clusters' bases or coefficients are not laid out one "
                             "after another as compress and build write them")
        self.has_mean = bool(int(f.attrs.get("has_mean", 0)))
        # Stored precision kept: float16 and int8 stay so in memory.
        self.bases = self._tensor(f["bases"][:]).view(-1, n)
        self.means = self._tensor(f["means"][:]).view(-1, n)
        self.coefficients = self._tensor(f["coefficients"][:])
        self.scale = self._tensor(f["coefficient_scale"][:]).to(torch.float32)
        if self.has_mean:
            self.row_cluster = self._tensor(
                np.repeat(np.arange(len(self.ranks)), np.diff(self.row_offsets)))
        self.spans = self._spans()
        if self.kernel == "sparse":
            row_rank = np.repeat(self.ranks, np.diff(self.row_offsets))
            self.row_first = self._tensor(
                np.repeat(self.first_basis[:-1], np.diff(self.row_offsets)))
            self.row_rank = self._tensor(row_rank)
            self.row_entries = self._tensor(np.concatenate([[0], np.cumsum(row_rank)]))

    def _tensor(self, array):
        return torch.from_numpy(np.ascontiguousarray(array)).to(self.device)

    def _spans(self):
        """Pieces (first row, last row, rank, first basis, first entry) of at
        most _SPAN_ENTRIES entries, grouped into spans of at most that many."""
        spans, span, entries = [], [], 0
        for c, rank in enumerate(self.ranks.tolist()):
            first, last = int(self.row_offsets[c]), int(self.row_offsets[c + 1])
            step = max(1, _SPAN_ENTRIES // max(1, rank))
            for start in range(first, last, step):
                stop = min(last, start + step)
                size = (stop - start) * rank
                if span and entries + size > _SPAN_ENTRIES:
                    spans.append(span)
                    span, entries = [], 0
                entry = int(self.entry_offsets[c]) + (start - first) * rank
                span.append((start, stop, rank, int(self.first_basis[c]), entry))
                entries += size
        if span:
            spans.append(span)
        return spans

    def relit(self, projected):
        """Each row's value under projected lightings V_g^T L [N, K]: [K, P]
        float32 (a column per row, so that images are made channels-first
        without a transpose), rows in cluster order, albedo not applied."""
        towards = torch.empty(int(self.first_basis[-1]), projected.shape[1],
                              dtype=torch.float32, device=self.device)
        for start in range(0, towards.shape[0], _BASIS_ROWS):
            stop = min(towards.shape[0], start + _BASIS_ROWS)
            torch.matmul(self.bases[start:stop].to(torch.float32), projected,
                         out=towards[start:stop])
        towards *= self.scale[:, None]
        out = torch.empty(projected.shape[1], self.rows, dtype=torch.float32, device=self.device)
        for span in self.spans:
            (self._sparse_span if self.kernel == "sparse" else self._dense_span)(span, towards, out)
        if self.has_mean:
            out += (projected.t() @ self.means.to(torch.float32).t())[:, self.row_cluster]
        return out

    def _dense_span(self, span, towards, out):
        entry0 = span[0][4]
        wide = self.coefficients[entry0:span[-1][4] + (span[-1][1] - span[-1][0]) * span[-1][2]]
        wide = wide.to(torch.float32)
        for start, stop, rank, basis, entry in span:
            if rank == 0:
                out[:, start:stop].zero_()
                continue
            u = wide[entry - entry0:entry - entry0 + (stop - start) * rank].view(stop - start, rank)
            # (u W^T)^T written straight into the strided columns.
            torch.matmul(towards[basis:basis + rank].t(), u.t(), out=out[:, start:stop])

    def _sparse_span(self, span, towards, out):
        first, last = span[0][0], span[-1][1]
        crow = self.row_entries[first:last + 1] - self.row_entries[first]
        entries = int(crow[-1])
        if entries == 0:
            out[:, first:last].zero_()
            return
        entry0 = span[0][4]
        values = self.coefficients[entry0:entry0 + entries].to(torch.float32)
        # Entry e of row p sits in column first(p) + (e - crow[p]).
        column = (torch.repeat_interleave(self.row_first[first:last] - crow[:-1],
                                          self.row_rank[first:last]) +
                  torch.arange(entries, device=self.device))
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="Sparse CSR tensor support is in beta")
            matrix = torch.sparse_csr_tensor(crow, column, values,
                                             size=(last - first, towards.shape[0]))
            out[:, first:last] = (matrix @ towards).t()
