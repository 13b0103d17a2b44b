#!/usr/bin/env python3
"""Runs every command the README and docs/ give a user, as written, after the README's
first command (`bash scripts/demo.sh`, which builds into build/release).

A command is a line of a fenced or indented code block that starts with
`build/release/` (optionally after `$ ` or `xvfb-run ... `). It runs from a scratch copy
of the checkout (so outputs such as out/ or bottle.haptic land there, in the order the
pages give them), with `build/release/` standing for the build tree under test. Under
a `$ ` line, the lines up to the block's end are the output the page promises: they
must match exactly, except that a line `...` stands for any number of lines (output the
page leaves out, such as timings). The editor started without --script would wait for a person, so
it gets a one-line script that quits once the window is up.

Not run: `bash scripts/*.sh` and `cmake` lines (the build itself), and
docs/BENCHMARKS.md (it configures its own build folder). Commands that read
../shared are skipped with a note when that folder is absent.

usage: run_doc_commands.py SOURCE_DIR BUILD_DIR
"""
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

PAGES = ["README.md", "docs/*.md", "samples/*/README.md"]
SKIP_PAGES = {"docs/BENCHMARKS.md"}
PREFIX = "build/release/"


def code_blocks(text):
    """Yields the lines of each code block: ``` fences and 4-space indented runs."""
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        fence = re.match(r"^(\s*)```", line)
        if fence:
            indent = len(fence.group(1))
            block = []
            i += 1
            while i < len(lines) and not lines[i].strip().startswith("```"):
                block.append(lines[i][indent:])
                i += 1
            yield block
            i += 1
            continue
        m = re.match(r"^( {4,})\S", line)
        if m and (i == 0 or lines[i - 1].strip() == ""):
            indent = len(m.group(1))
            block = []
            while i < len(lines) and (lines[i].startswith(" " * indent) or lines[i].strip() == ""):
                if lines[i].strip() == "" and (i + 1 >= len(lines) or not lines[i + 1].startswith(" " * indent)):
                    break
                block.append(lines[i][indent:])
                i += 1
            yield block
            continue
        i += 1


def commands(page_text):
    """(command, expected output or None) pairs in page order."""
    for block in code_blocks(page_text):
        # A line ending in a backslash continues on the next.
        joined = []
        for raw in block:
            if joined and joined[-1].rstrip().endswith("\\"):
                joined[-1] = joined[-1].rstrip()[:-1] + " " + raw.strip()
            else:
                joined.append(raw)
        block = joined
        j = 0
        while j < len(block):
            line = block[j].strip()
            shown = line.startswith("$ ")
            cmd = line[2:] if shown else line
            cmd = re.sub(r"\s+#\s.*$", "", cmd)  # a trailing comment
            try:
                words = shlex.split(cmd) if cmd else []
            except ValueError:  # prose or output in a block, not a shell line
                words = []
            runs = words and (words[0].startswith(PREFIX) or
                              (words[0] == "xvfb-run" and any(w.startswith(PREFIX) for w in words)))
            if not runs:
                j += 1
                continue
            expected = None
            if shown:
                out = []
                j += 1
                while j < len(block) and not block[j].strip().startswith("$ "):
                    out.append(block[j])
                    j += 1
                while out and out[-1].strip() == "":
                    out.pop()
                expected = "\n".join(out)
            else:
                j += 1
            yield cmd, expected


def matches(printed, expected):
    """True when the printed lines are the expected ones, each `...` line standing for
    any run of lines (none included)."""
    got = printed.split("\n")
    want = expected.split("\n")
    # Greedy-free matching by dynamic programming over the two line lists.
    reach = [[False] * (len(got) + 1) for _ in range(len(want) + 1)]
    reach[0][0] = True
    for i in range(1, len(want) + 1):
        wild = want[i - 1].strip() == "..."
        for j in range(len(got) + 1):
            if wild:
                reach[i][j] = reach[i - 1][j] or (j > 0 and reach[i][j - 1])
            else:
                reach[i][j] = j > 0 and reach[i - 1][j - 1] and got[j - 1] == want[i - 1]
    return reach[len(want)][len(got)]


def main():
    source = pathlib.Path(sys.argv[1]).resolve()
    build = pathlib.Path(sys.argv[2]).resolve()
    shared = source.parent / "shared"
    pages = []
    for pattern in PAGES:
        pages += sorted(p for p in source.glob(pattern) if str(p.relative_to(source)) not in SKIP_PAGES)
    scratch = pathlib.Path(tempfile.mkdtemp(prefix="annex_doc_commands_"))
    work = scratch / "annex"
    shutil.copytree(source, work, ignore=shutil.ignore_patterns(".git", "build*", "out"))
    (work / "build").mkdir()
    os.symlink(build, work / "build" / "release")
    quit_script = scratch / "quit.script"
    quit_script.write_text("frames 2\nquit\n")
    env = dict(os.environ)
    env.setdefault("ANNEX_AUTHOR_STATE_DIR", str(scratch / "state"))
    ran, failed, skipped = 0, [], []
    for page in pages:
        rel = page.relative_to(source)
        for cmd, expected in commands(page.read_text()):
            if "../shared" in cmd and not shared.is_dir():
                skipped.append(f"{rel}: {cmd} (../shared is absent)")
                continue
            words = shlex.split(cmd)
            run = cmd
            if words[0].endswith("annex-author") and "--script" not in words:
                run = cmd + " --script " + shlex.quote(str(quit_script))
            if words[0].endswith("annex-author"):
                run = "xvfb-run -a -s '-screen 0 1600x900x24' " + run
            try:
                r = subprocess.run(run, shell=True, cwd=work, env=env, capture_output=True,
                                   text=True, timeout=600)
            except subprocess.TimeoutExpired:
                failed.append(f"{rel}: {cmd}\n    timed out")
                continue
            ran += 1
            if r.returncode != 0:
                failed.append(f"{rel}: {cmd}\n    exit {r.returncode}\n    " +
                              (r.stderr.strip() or r.stdout.strip()).replace("\n", "\n    "))
            elif expected is not None and not matches(r.stdout.rstrip("\n"), expected):
                failed.append(f"{rel}: {cmd}\n    printed:\n{r.stdout}    the page shows:\n{expected}")
            else:
                print(f"ok  {rel}: {cmd}")
    for s in skipped:
        print(f"skip {s}")
    shutil.rmtree(scratch, ignore_errors=True)
    print(f"{ran} commands run, {len(failed)} failed, {len(skipped)} skipped")
    for f in failed:
        print(f"FAIL {f}", file=sys.stderr)
    if ran < 10:
        print("FAIL fewer than 10 commands found: the extraction is broken", file=sys.stderr)
        return 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
