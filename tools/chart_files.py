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
    """OUT_DIR/STEM.svg and .png, each written beside its place and renamed into it only when complete (a
    failed write leaves no part behind); `options` go to savefig (e.g. bbox_inches="tight")."""
    for ext in ("svg", "png"):
        path = os.path.join(out_dir, f"{stem}.{ext}")
        try:
            fig.savefig(path + ".part", format=ext, dpi=dpi, metadata=METADATA[ext], **options)
        except BaseException:
            if os.path.exists(path + ".part"):
                os.remove(path + ".part")
            raise
        os.replace(path + ".part", path)
    plt.close(fig)


def _invisible(c):
    """The characters src/text/text/shown.hpp shows by code point: controls, no-break and typographic
    spaces, zero-width characters, direction marks, the byte-order mark, U+FFFE and U+FFFF."""
    return (c < 0x20 or 0x7F <= c <= 0xA0 or c == 0xAD or 0x2000 <= c <= 0x200F or 0x2028 <= c <= 0x202F
            or 0x205F <= c <= 0x206F or c == 0x3000 or c == 0xFEFF or 0xFFF9 <= c <= 0xFFFB or c in (0xFFFE, 0xFFFF)
            or 0xD800 <= c <= 0xDFFF)


def shown(text):
    """`text` as humandyn's messages show it (text::shown): tab, line feed, carriage return and backslash as
    \\t \\n \\r \\\\, a space at either end as \u2420, other invisible characters as <U+XXXX>, and a byte that is not
    UTF-8 (a file name's, which Python holds as a lone surrogate) as <0xXX>. Chart titles go through it: an
    SVG can carry neither a control character nor a lone surrogate."""
    lead, trail = len(text) - len(text.lstrip(" ")), len(text.rstrip(" "))
    out = []
    for i, ch in enumerate(text):
        c = ord(ch)
        if 0xDC80 <= c <= 0xDCFF:
            out.append(f"<0x{c - 0xDC00:02X}>")
        elif ch in "\t\n\r\\":
            out.append({"\t": "\\t", "\n": "\\n", "\r": "\\r", "\\": "\\\\"}[ch])
        elif ch == " " and (i < lead or i >= trail):
            out.append("\u2420")
        elif _invisible(c):
            out.append(f"<U+{c:04X}>")
        else:
            out.append(ch)
    return "".join(out)
