#!/usr/bin/env python3
"""The pictures of the README and the docs are the ones scripts/update_pictures.sh
makes from this build's runs, small, and shown.

Usage: check_pictures.py <repo> <build dir> <scratch dir>

1. The script makes every picture again in the scratch folder (a real run of
   symdyn-sim, gnuplot and headless Chromium).
2. Each committed picture in docs/images has the size in pixels of the new one
   and the same pixels but for a few (at most 0.5 % differ by more than 48 in a
   channel: anti-aliasing and the last bits of a run may move, a stale plot or
   view does not stay within that); each is under 150 kB.
3. docs/images holds no other picture, and each is shown by README.md or a page
   of docs/.
"""
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "viewer"))
from check_viewer import read_png  # noqa: E402

MAX_BYTES = 150_000
MAX_CHANGED_SHARE = 0.005


def changed_share(old, new):
    (w0, h0, rows0), (w1, h1, rows1) = old, new
    if (w0, h0) != (w1, h1):
        return None
    changed = sum(1 for r0, r1 in zip(rows0, rows1) for p0, p1 in zip(r0, r1)
                  if max(abs(a - b) for a, b in zip(p0, p1)) > 48)
    return changed / (w0 * h0)


def main():
    repo, build, scratch = Path(sys.argv[1]), sys.argv[2], Path(sys.argv[3])
    scratch.mkdir(parents=True, exist_ok=True)
    done = subprocess.run(["bash", str(repo / "scripts/update_pictures.sh"), build, str(scratch)],
                          capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        sys.exit(f"scripts/update_pictures.sh failed: {done.stderr[-2000:]}")
    made = sorted(p.name for p in scratch.glob("*.png"))
    committed = sorted(p.name for p in (repo / "docs/images").glob("*.png"))
    if made != committed:
        sys.exit(f"docs/images holds {committed}, scripts/update_pictures.sh makes {made}")
    pages = [repo / "README.md", *sorted((repo / "docs").glob("*.md"))]
    text = "".join(page.read_text() for page in pages)
    failures = []
    for name in made:
        old_path, new_path = repo / "docs/images" / name, scratch / name
        size = old_path.stat().st_size
        if size > MAX_BYTES or new_path.stat().st_size > MAX_BYTES:
            failures.append(f"{name}: {size} bytes committed, {new_path.stat().st_size} made; "
                            f"at most {MAX_BYTES}")
        share = changed_share(read_png(old_path), read_png(new_path))
        if share is None:
            failures.append(f"{name}: not the size in pixels of the picture the script makes")
        elif share > MAX_CHANGED_SHARE:
            failures.append(f"{name}: {share:.2%} of its pixels differ from the picture the script "
                            f"makes now (at most {MAX_CHANGED_SHARE:.1%})")
        else:
            print(f"{name}: {size} bytes, {share:.3%} of its pixels differ from a new run")
        if f"images/{name}" not in text:
            failures.append(f"{name}: shown by no page (README.md, docs/*.md)")
    if failures:
        sys.exit("\n".join(failures) + "\nrun scripts/update_pictures.sh and commit docs/images")
    print(f"{len(made)} pictures as scripts/update_pictures.sh makes them")


if __name__ == "__main__":
    main()
