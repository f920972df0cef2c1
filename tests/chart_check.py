"""What the chart checks share: a PNG file's structure and an SVG file's text.

Imported by tests/plot_bench_check.py and tests/plot_torques_check.py (from the folder they stand in).
"""

import struct
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"


def check_png(path):
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG signature"
    length, kind = struct.unpack(">I4s", data[8:16])
    assert kind == b"IHDR" and length == 13, f"{path}: no IHDR chunk first"
    width, height = struct.unpack(">II", data[16:24])
    assert width >= 600 and height >= 300, f"{path}: {width} x {height} pixels, too small to read"
    assert data[-12:-4] == b"\x00\x00\x00\x00IEND", f"{path}: does not end with IEND (truncated?)"


def svg_text(path):
    """Every text of the SVG, joined by spaces; raises on malformed XML or a root that is not <svg>."""
    root = ET.parse(path).getroot()
    assert root.tag == SVG + "svg", f"{path}: root element is {root.tag}"
    return " ".join("".join(t.itertext()) for t in root.iter(SVG + "text"))
