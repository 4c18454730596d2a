#!/usr/bin/env python3
"""Opens symdyn's HTML viewer in headless Chromium and checks that it draws.

Usage: check_viewer.py <chromium> <file.html> <work dir>

1. The page loads without error and lists its clips (the DOM after load).
2. Screenshots at t = 0 and t = 0.7 s (the viewer's #t= start) show the bodies
   (dark or saturated pixels, unlike the grey floor) and differ in the 3D view:
   the animation moves.
3. A mode clip (#clip=1) draws too, unlike the motion at the same time.
"""
import struct
import subprocess
import sys
import zlib
from pathlib import Path

FLAGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
         "--enable-unsafe-swiftshader", "--hide-scrollbars", "--window-size=900,600",
         "--virtual-time-budget=4000"]


def chromium(browser, *args):
    done = subprocess.run([browser, *FLAGS, *args], capture_output=True, text=True, timeout=120)
    if done.returncode != 0:
        sys.exit(f"chromium failed ({done.returncode}): {done.stderr[-2000:]}")
    return done.stdout


def read_png(path):
    """Width, height and RGB rows of an 8-bit RGB or RGBA PNG (what Chromium writes)."""
    data = path.read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour = header[:4]
    if depth != 8 or colour not in (2, 6):
        sys.exit(f"{path}: unexpected PNG format (depth {depth}, colour type {colour})")
    channels = 3 if colour == 2 else 4
    raw, stride, rows, prev = zlib.decompress(idat), width * channels, [], bytearray(width * channels)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):  # undo the PNG filter of the row
            a = line[x - channels] if x >= channels else 0
            b, c = prev[x], prev[x - channels] if x >= channels else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x:x + 3]) for x in range(0, stride, channels)])
        prev = line
    return width, height, rows


def view_pixels(rows):
    """The 3D view: the left 60 % of the page, above the control bar."""
    height, width = len(rows), len(rows[0])
    return [px for row in rows[20:height - 60] for px in row[:width * 6 // 10]]


def drawn(pixels):
    """The share of pixels in the bodies' colours: dark or saturated, unlike the
    light grey background, floor and grid."""
    return sum(1 for p in pixels if 255 * 3 - sum(p) > 200 or max(p) - min(p) > 60) / len(pixels)


def main():
    browser, html, work = sys.argv[1], Path(sys.argv[2]).resolve(), Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    dom = chromium(browser, "--dump-dom", html.as_uri())
    if "data-error=" in dom:
        sys.exit("the viewer reported an error: " + dom[dom.index("data-error="):][:300])
    if 'data-ready="true"' not in dom:
        sys.exit("the viewer did not finish loading")
    for clip in ("motion", "mode 1:", "mode 2:"):
        if clip not in dom:
            sys.exit(f"clip '{clip}' missing from the page")

    shots = {}
    for name, hash_ in (("start", "t=0"), ("later", "t=0.7"), ("mode", "clip=1&t=0.7")):
        png = work / f"viewer_{name}.png"
        png.unlink(missing_ok=True)
        chromium(browser, f"--screenshot={png}", f"{html.as_uri()}#{hash_}")
        shots[name] = view_pixels(read_png(png)[2])

    for name, pixels in shots.items():
        share = drawn(pixels)
        print(f"{name}: {share:.3%} of the view shows the bodies")
        if share < 0.005:
            sys.exit(f"screenshot '{name}' is blank: nothing drawn in the 3D view")
    for a, b in (("start", "later"), ("later", "mode")):
        moved = sum(1 for p, q in zip(shots[a], shots[b]) if sum(abs(u - v) for u, v in zip(p, q)) > 30)
        print(f"{a} -> {b}: {moved / len(shots[a]):.3%} of the view changed")
        if moved < 0.002 * len(shots[a]):
            sys.exit(f"screenshots '{a}' and '{b}' are the same: the animation does not move")
    print("viewer draws and moves")


if __name__ == "__main__":
    main()
