"""Running a campaign: the MPI driver, per-case storage, the campaign dataset, progress.

:mod:`.progress` (rank-aware logging) and :mod:`.storage` (per-case files, atomic writes,
failure records) at the bottom, :mod:`.assemble` (one CF dataset per campaign) on storage,
:mod:`.driver` (dynamic distribution of cases over MPI ranks) on top.
"""
