#!/usr/bin/env python3
"""Keeps the code blocks of the user documentation true.

  code_blocks.py check <repo> [<page>...] every block of each page (without pages:
      of every page in COVERED) is one of:
      ```<lang> file=<path>   the text of <path>, which the build compiles and the
                              tests run: it must be that file, byte for byte;
      ```<lang> in=<path>     lines of <path> (a line of a CMakeLists.txt the
                              build reads): each must be a line of it;
      ```sh run               commands the tutorial test runs (see `script`);
      ```sh ci                commands .ci/run runs: each line must be in it;
      ```text                 output shown, not code.
      Without pages, every page of docs/ must also be in COVERED or NOT_COVERED,
      so that a new page is covered or said not to be.
  code_blocks.py script <repo> <page>     prints a bash script that does what the
      page says, in order: each `file=` block written to its file name in the
      current folder, each `sh run` block run.

The pages covered: README.md, docs/tutorial.md, docs/runtime.md (its programs are
tests/docs/fixtures/runtime_*.cpp), docs/builder.md (its model file is
tests/docs/fixtures/builder_slider_crank.cpp, its --describe output
tests/docs/fixtures/double_pendulum_relative.json), docs/python.md (its example is
tests/python/documented_example.py, which test_example.py runs), docs/scenarios.md
(its example is tests/docs/fixtures/swing.json, which run_scenarios.sh runs with its
commands; its fragments lines of it or of models/scenarios/trike.json), docs/urdf.md
(its example is tests/docs/urdf_pendulum, built when symdyn-urdf is; its fragments lines
of it, of tests/urdf and of src/model/urdf.hpp), docs/emitted_interface.md (its header is
tests/docs/fixtures/emitted_interface.hpp, which emitted_interface_check.cpp compiles
against the one emitted for double_pendulum_absolute), docs/sweeps.md (its sweep files
are those of models/sweeps, its Python example tests/sweep/documented_example.py, which
test_sweep_runs.py runs; its commands, tests/docs/fixtures/sweep_trike.py and its Slurm
script fixtures/slurm_sweep.sh are run by run_sweeps.sh on this machine), docs/install.md
(its example's CMakeLists.txt is examples/spinning_top's; its commands lines of
run_install.sh, which installs this build and builds the example, of
tests/package/programs_test.sh and of tests/package/deb_test.sh, which scripts/test.sh runs
as root), and docs/design.md,
docs/errors.md, docs/integrators.md, docs/models.md (output and diagrams only, or no block).
"""
import re
import sys
from pathlib import Path

FENCE = re.compile(r"^```(\S*)(.*)$")
COVERED = ["README.md", "docs/tutorial.md", "docs/runtime.md", "docs/builder.md", "docs/python.md",
           "docs/scenarios.md", "docs/urdf.md", "docs/emitted_interface.md", "docs/sweeps.md", "docs/install.md",
           "docs/design.md", "docs/errors.md", "docs/integrators.md", "docs/models.md"]
NOT_COVERED = []


def blocks(page):
    """(line number, language, attributes, text) of every fenced block."""
    found, lines, at = [], page.read_text().splitlines(keepends=True), 0
    while at < len(lines):
        opening = FENCE.match(lines[at].rstrip("\n"))
        if not opening:
            at += 1
            continue
        start, body = at + 1, []
        at += 1
        while at < len(lines) and lines[at].rstrip("\n") != "```":
            body.append(lines[at])
            at += 1
        if at == len(lines):
            sys.exit(f"{page}:{start}: the code block never closes")
        attributes = dict(a.split("=", 1) if "=" in a else (a, True) for a in opening.group(2).split())
        found.append((start, opening.group(1), attributes, "".join(body)))
        at += 1
    return found


def unlisted(repo):
    """The pages of docs/ neither in COVERED nor in NOT_COVERED."""
    listed = set(COVERED + NOT_COVERED)
    return [f"{page}: a page neither covered nor listed as not covered (code_blocks.py)"
            for page in sorted(p.relative_to(repo).as_posix() for p in (repo / "docs").glob("*.md"))
            if page not in listed]


def check(repo, pages):
    ci = (repo / ".ci" / "run").read_text()
    errors = [] if pages else unlisted(repo)
    pages = pages or [repo / p for p in COVERED]
    for page in pages:
        for line, lang, attributes, text in blocks(page):
            where = f"{page.relative_to(repo)}:{line}"
            if "file" in attributes:
                source = repo / attributes["file"]
                if not source.is_file():
                    errors.append(f"{where}: {attributes['file']} does not exist")
                elif source.read_text() != text:
                    errors.append(f"{where}: differs from {attributes['file']}: copy the file into the page again")
            elif "in" in attributes:
                source = repo / attributes["in"]
                known = set(source.read_text().splitlines()) if source.is_file() else set()
                for quoted in filter(None, text.splitlines()):
                    if quoted not in known:
                        errors.append(f"{where}: '{quoted}' is not a line of {attributes['in']}")
            elif lang == "sh" and attributes.get("ci"):
                for command in filter(None, (c.split("#")[0].strip() for c in text.splitlines())):
                    if command not in ci:
                        errors.append(f"{where}: '{command}' is not run by .ci/run")
            elif lang == "sh" and attributes.get("run"):
                pass
            elif lang != "text":
                errors.append(f"{where}: a ```{lang} block that no test compiles or runs "
                              "(quote a file with file=, or mark commands run/ci)")
    for e in errors:
        print(e, file=sys.stderr)
    return 1 if errors else 0


def script(page):
    out = ["set -euo pipefail"]
    for _, lang, attributes, text in blocks(page):
        if "file" in attributes:
            name = Path(attributes["file"]).name
            out.append(f"cat > {name} <<'SYMDYN_DOC_EOF'\n{text}SYMDYN_DOC_EOF")
        elif lang == "sh" and attributes.get("run"):
            out.append(text.rstrip("\n"))
    print("\n".join(out))
    return 0


if __name__ == "__main__":
    command, repo = sys.argv[1], Path(sys.argv[2]).resolve()
    pages = [repo / p for p in sys.argv[3:]]
    sys.exit(check(repo, pages) if command == "check" else script(pages[0]))
