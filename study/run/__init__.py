"""Running a campaign: the MPI driver, stored cases, the campaign dataset, progress.

From the bottom up: :mod:`.progress` (rank-aware logging); :mod:`.storage` (the output
folder: which cases it holds, in :mod:`study.bundle` files or older per-case files, atomic
writes, corrupt files); :mod:`.assemble` (one CF dataset per campaign, from the rows each
case's rank computed); :mod:`.writer` (what is stored of a solved case, a rank's bundle
writer); :mod:`.scheduler` (the queue, reports and stopping rules on rank 0); :mod:`.driver`
(dynamic distribution of cases over MPI ranks) on top.
"""
