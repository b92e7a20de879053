# SPDX-License-Identifier: BSD-3-Clause
"""The transfer study's figure (docs/transfer.md): per target, the 95th percentile error of
the three methods on the subset and remesh cases, from `TransferStudy --csv FILE`.

    python3 TransferStudyPlot.py study.csv docs/images/transfer_per_target.png

Needs matplotlib (Debian python3-matplotlib); run by hand with the study, not in CI."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1])))
cases = ["subset", "remesh", "landmarks +-2 mm"]
methods = ["nearest vertex", "barycentric", "deformation transfer"]
targets = [r["target"] for r in rows if r["case"] == "remesh" and r["method"] == methods[0]]
fig, axes = plt.subplots(len(cases), 1, figsize=(13, 9), sharex=True)
for ax, case in zip(axes, cases):
    for m, marker in zip(methods, "o^s"):
        p95 = {r["target"]: max(float(r["p95_mm"]), 1e-4) for r in rows
               if r["case"] == case and r["method"] == m}
        ax.semilogy(range(len(targets)), [p95[t] for t in targets], marker, label=m, markersize=4)
    ax.axhline(0.5, color="red", linewidth=0.8, label="goal 0.5 mm")
    ax.set_ylabel("p95 error (mm)")
    ax.set_title(case, fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
axes[0].legend(ncol=4, fontsize=8)
axes[-1].set_xticks(range(len(targets)))
axes[-1].set_xticklabels(targets, rotation=90, fontsize=7)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=90)
