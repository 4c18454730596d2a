#!/usr/bin/env python3
"""symdyn-sim's HTML viewer of the trike, read two ways.

Usage: check_trike_viewer.py <symdyn-sim> <chromium> <work dir>

1. The page's data: the glTF inside holds the shapes of the trike's scenario
   (models/scenarios/trike.json, "shapes"): a wheel is a cylinder of radius
   0.3 and width 0.12 about its y axis in the colour written, the chassis its
   six shapes; the coordinates' units tell metres from radians.
2. In headless Chromium the camera follows the trike: at the start and 4.5 s
   later (22 m on) the trike fills a good part of the view, not a few pixels.
"""
import base64
import json
import re
import struct
import subprocess
import sys
from pathlib import Path

from check_viewer import chromium, drawn, read_png, view_pixels


def glb_of(html):
    data = json.loads(re.search(r'<script id="symdyn-data" type="application/json">(.*?)</script>',
                                html, re.S).group(1).replace("<\\/", "</"))
    glb = base64.b64decode(data["glb"])
    magic, _, _ = struct.unpack("<III", glb[:12])
    assert magic == 0x46546C67, "not a glTF binary"
    length, _ = struct.unpack("<II", glb[12:20])
    doc = json.loads(glb[20:20 + length])
    bin_start = 20 + length + 8
    return data, doc, glb[bin_start:]


def positions(doc, binary, accessor):
    a = doc["accessors"][accessor]
    view = doc["bufferViews"][a["bufferView"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    values = struct.unpack(f"<{3 * a['count']}f", binary[start:start + 12 * a["count"]])
    return [values[k:k + 3] for k in range(0, len(values), 3)]


def check_data(html):
    data, doc, binary = glb_of(html)
    nodes = {n["name"]: n for n in doc["nodes"]}
    for wheel in ("left_rear_wheel", "right_rear_wheel", "front_wheel"):
        primitives = doc["meshes"][nodes[wheel]["mesh"]]["primitives"]
        if len(primitives) != 2:
            sys.exit(f"{wheel}: {len(primitives)} shapes, the scenario gives 2")
        points = positions(doc, binary, primitives[0]["attributes"]["POSITION"])
        low = [min(p[k] for p in points) for k in range(3)]
        high = [max(p[k] for p in points) for k in range(3)]
        expected = ([-0.3, -0.06, -0.3], [0.3, 0.06, 0.3])
        if any(abs(a - b) > 1e-4 for a, b in zip(low + high, expected[0] + expected[1])):
            sys.exit(f"{wheel}: the tyre spans {low} .. {high}, not a cylinder r 0.3, width 0.12 about y")
        colour = doc["materials"][primitives[0]["material"]]["pbrMetallicRoughness"]["baseColorFactor"]
        if any(abs(a - b) > 1e-3 for a, b in zip(colour, [0x33 / 255, 0x33 / 255, 0x36 / 255, 1])):
            sys.exit(f"{wheel}: colour {colour}, the scenario gives #333336")
    chassis = len(doc["meshes"][nodes["chassis"]["mesh"]]["primitives"])
    if chassis != 6:
        sys.exit(f"chassis: {chassis} shapes, the scenario gives 6")
    units = data["series"]["units"]
    expected_units = ["s", "m", "m", "m", "rad", "rad", "rad", "m", "rad", "rad", "rad", "rad", "m", "rad"]
    if units != expected_units:
        sys.exit(f"series units {units}, expected {expected_units}")
    print("the page holds the scenario's shapes and the coordinates' units")


def main():
    sim, browser, work = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    html = work / "trike.html"
    done = subprocess.run([sim, "trike", "--out", str(work / "trike.csv"), "--html", str(html)],
                          capture_output=True, text=True, timeout=300)
    if done.returncode != 0:
        sys.exit(f"symdyn-sim trike failed: {done.stderr[-2000:]}")
    check_data(html.read_text())

    dom = chromium(browser, "--dump-dom", html.resolve().as_uri())
    if 'data-ready="true"' not in dom or 'data-follow="true"' not in dom:
        sys.exit("the viewer did not load, or does not follow the trike")
    for name, time in (("start", 0), ("later", 4.5)):
        png = work / f"trike_{name}.png"
        png.unlink(missing_ok=True)
        chromium(browser, f"--screenshot={png}", f"{html.resolve().as_uri()}#t={time}")
        share = drawn(view_pixels(read_png(png)[2]))
        print(f"t = {time} s: the trike covers {share:.2%} of the view")
        if share < 0.03:
            sys.exit(f"at t = {time} s the trike covers {share:.2%} of the view: it is not framed")
    print("viewer frames and follows the trike")


if __name__ == "__main__":
    main()
