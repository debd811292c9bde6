"""The figures of a run read by Python's own XML parser and a PNG reader written here from the PNG
specification (signature, IHDR, IDAT through zlib, the five scanline filters): every SVG is XML with an
<svg> root of the PNG's size and the axis labels with their units as text elements; every PNG decodes
and is not blank."""

import struct
import xml.etree.ElementTree as ET
import zlib

from conftest import run_satflock

SVG = "{http://www.w3.org/2000/svg}"


def read_png(path):
    """Width, height and rows of RGB(A) pixel tuples of an 8-bit truecolour PNG."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG signature"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (2, 6) and interlace == 0, f"{path}: {header}"
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        line = raw[y * (stride + 1) : (y + 1) * (stride + 1)]
        kind, row = line[0], bytearray(line[1:])
        for i in range(stride):
            a = row[i - channels] if i >= channels else 0
            b = previous[i]
            c = previous[i - channels] if i >= channels else 0
            if kind == 1:
                row[i] = (row[i] + a) & 0xFF
            elif kind == 2:
                row[i] = (row[i] + b) & 0xFF
            elif kind == 3:
                row[i] = (row[i] + (a + b) // 2) & 0xFF
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                row[i] = (row[i] + pred) & 0xFF
        rows.append([tuple(row[x : x + 3]) for x in range(0, stride, channels)])
        previous = row
    return width, height, rows


def test_figures_parse_and_carry_labelled_axes(satflock_bin, tmp_path):
    out = tmp_path / "run"
    run_satflock(satflock_bin, "run", "es-e0", "--out", str(out), "--quiet")
    labels = {
        "trajectories": ["x radial [m]", "y along-track [m]", "z orbit normal [m]", "kinetic-threat"],
        "snapshots": ["t = 0 s (start)"],
        "swarm_metrics": ["t [s]", "d_max [m]", "uniformity_l [-]", "min_separation [m]"],
        "law_metrics": ["es_formation_error [m]"],
        "delta_v": ["Δv [m/s]", "satellite id [-]"],
    }
    for name, expected in labels.items():
        root = ET.parse(out / "plots" / f"{name}.svg").getroot()
        assert root.tag == f"{SVG}svg"
        texts = {" ".join(t.text.split()) for t in root.iter(f"{SVG}text") if t.text}
        for label in expected:
            assert any(label in t for t in texts), f"{name}.svg: no text `{label}`"
        width, height, rows = read_png(out / "plots" / f"{name}.png")
        assert (width, height) == (int(root.get("width")), int(root.get("height")))
        white = (255, 255, 255)
        assert rows[0][0] == white
        inked = sum(1 for row in rows for p in row if p != white)
        assert inked > 0.01 * width * height, f"{name}.png is nearly blank"
