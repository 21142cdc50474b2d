"""Incremental sparse row echelon form over Z/pZ.

Rows arrive one at a time (order by order of Lie derivatives); the echelon form
is kept fully reduced, so a new row is reduced in one pass and the null space
and the observable coordinates can be read off at any moment. Pivots are chosen
to keep fill-in low: among a new row's entries, the column that the fewest
stored rows touch. In a SLAM problem that is a landmark's own column, so the
elimination stays block-sparse and costs time linear in the number of landmarks.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

__all__ = ["ModularEchelon", "RANK_PRIME"]

#: The prime of the ranks taken modulo a prime (the completion's echelon form, the global
#: stage's ``rank_mod_prime``): Mersenne, below 2^64 for flint's word-size matrices.
RANK_PRIME = 2**61 - 1


class ModularEchelon:
    """Reduced row echelon form of a growing set of sparse rows modulo ``p``.

    Parameters
    ----------
    n_columns : int
    p : int
        A prime.
    order : sequence of int, optional
        A rank per column: the pivot of a new row is then its entry of lowest
        rank, which makes the reduced form the canonical one for that column
        order (instead of the one with the least fill-in).
    """

    def __init__(self, n_columns: int, p: int, order: Sequence[int] | None = None) -> None:
        self.n_columns = n_columns
        self.p = p
        self.order = order
        self.pivot_rows: dict[int, dict[int, int]] = {}  # pivot column -> row (pivot entry 1)
        self.touching: dict[int, set[int]] = {}  # column -> pivot columns whose rows hold it

    @property
    def rank(self) -> int:
        return len(self.pivot_rows)

    def add_row(self, row: Mapping[int, int]) -> bool:
        """Add a row ``{column: value}``; return whether the rank grew."""
        p = self.p
        work = {c: v % p for c, v in row.items() if v % p}
        for col in [c for c in work if c in self.pivot_rows]:
            factor = work.get(col, 0)
            if factor:
                for c, v in self.pivot_rows[col].items():
                    nv = (work.get(c, 0) - factor * v) % p
                    if nv:
                        work[c] = nv
                    else:
                        work.pop(c, None)
        if not work:
            return False
        if self.order is not None:
            pivot = min(work, key=self.order.__getitem__)
        else:
            pivot = min(work, key=lambda c: (len(self.touching.get(c, ())), -c))
        inv = pow(work[pivot], -1, p)
        new = {c: v * inv % p for c, v in work.items()}
        # Keep the form reduced: clear the new pivot column from stored rows.
        for other in list(self.touching.get(pivot, ())):
            stored = self.pivot_rows[other]
            factor = stored[pivot]
            for c, v in new.items():
                nv = (stored.get(c, 0) - factor * v) % p
                if nv:
                    if c not in stored:
                        self.touching.setdefault(c, set()).add(other)
                    stored[c] = nv
                else:
                    if c in stored:
                        del stored[c]
                        self.touching[c].discard(other)
        self.pivot_rows[pivot] = new
        for c in new:
            if c != pivot:
                self.touching.setdefault(c, set()).add(pivot)
        return True

    def free_columns(self) -> list[int]:
        return [c for c in range(self.n_columns) if c not in self.pivot_rows]

    def null_space(self) -> list[dict[int, int]]:
        """A basis of the right null space, one sparse vector per free column."""
        basis = []
        for free in self.free_columns():
            vector = {free: 1}
            for pivot in self.touching.get(free, ()):
                vector[pivot] = -self.pivot_rows[pivot][free] % self.p
            basis.append(vector)
        return basis

    def determined_columns(self) -> list[int]:
        """Columns whose unit vector lies in the row space.

        Column c is determined exactly when every null vector vanishes at c: it is
        a pivot whose reduced row has no entry in a free column.
        """
        free = set(self.free_columns())
        return [c for c, row in sorted(self.pivot_rows.items()) if not (set(row) & free)]
