"""Writes one benchmark's section into docs/benchmarks.md, replacing the
section of the same heading or appending it. Every bench script uses this,
so the sections never clobber each other."""
import os
import re


def write_section(path, heading, section):
    """Puts `section` (which starts with `## heading`) into the file `path`
    when asked (LDAE_BENCH_DOC=1, set by a script's --doc): a benchmark run
    never rewrites tracked files by itself. Otherwise prints the section."""
    if os.environ.get("LDAE_BENCH_DOC") != "1":
        print(section.strip("\n"))
        print("(docs/benchmarks.md not written: pass --doc)")
        return
    try:
        text = open(path).read()
    except FileNotFoundError:
        text = "# Benchmarks\n"
    section = section.strip("\n") + "\n"
    pattern = re.compile(r"^## " + re.escape(heading) + r"\n.*?(?=^## |\Z)", re.S | re.M)
    if pattern.search(text):
        text = pattern.sub(lambda m: section + "\n", text, count=1)
    else:
        text = text.rstrip("\n") + "\n\n" + section
    with open(path, "w") as f:
        f.write(text.rstrip("\n") + "\n")
