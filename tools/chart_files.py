"""What the charts of tools/ share: matplotlib drawing to files only (no display), SVG whose text stays text
and whose bytes depend on the input alone, and each chart written as SVG and PNG.

Imported by tools/plot_bench.py and tools/plot_torques.py (from the folder they stand in).
"""

import os

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

plt.rcParams.update({
    "svg.fonttype": "none",      # text stays text in the SVG
    "svg.hashsalt": "humandyn",  # the same input gives the same SVG
    "font.size": 9,
    "axes.titlesize": 10,
})
METADATA = {"svg": {"Date": None}, "png": {}}


def save(fig, out_dir, stem, dpi, **options):
    """OUT_DIR/STEM.svg and .png, each written beside its place and renamed into it only when complete;
    `options` go to savefig (e.g. bbox_inches="tight")."""
    for ext in ("svg", "png"):
        path = os.path.join(out_dir, f"{stem}.{ext}")
        fig.savefig(path + ".part", format=ext, dpi=dpi, metadata=METADATA[ext], **options)
        os.replace(path + ".part", path)
    plt.close(fig)
