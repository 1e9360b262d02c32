#!/usr/bin/env python3
"""Mutation test of the whole ldaec pipeline (stdlib only).

Every .lsd file of the repository (examples/, tests/, stdlib/) is corrupted
with token-aware mutations and each mutant is run through every stage of the
`ldaec` command (flat, analysis, simulation, C and LLVM emission) under a
memory cap and a CPU-time limit. A stage run fails on a signal, an abort text, a
hang, an exit code outside 0..3, or a model error (exit 1) with no
`file:line:col: error:` line. Mutant k depends only on (seed, k), so a
failure is reproduced by the same --seed and --count, whatever --jobs is.

Usage (see docs/hardening.md):
  mutate.py --ldaec build/compiler/driver/ldaec --work-dir DIR
            [--count 2000] [--seed 1] [--jobs 2] [--timeout 10] [--mem-gb 3]
"""

import argparse
import math
import collections
import multiprocessing
import os
import random
import re
import resource
import signal
import subprocess
import sys
import time

# The stages of the ldaec command a mutant goes through. The simulation is
# short; the interpreter (--jit off) starts faster than the JIT, which every
# fourth mutant uses instead so the JIT sees mutants too.
STAGES = [
    ("flat", ["--emit", "flat"]),
    ("analyze", ["--analyze", "--json"]),
    ("simulate", ["--simulate", "--stop", "0.1", "--no-progress"]),
    ("c", ["--emit", "c"]),
    ("llvm", ["--emit", "llvm"]),
]

# Texts that mean the process died rather than reported an error.
ABORT_TEXTS = [
    "terminate called",
    "Assertion `",  # glibc's assert(); not the word in a message
                     # ("AssertionLevel.error")
    "AddressSanitizer",
    "LeakSanitizer",
    "runtime error:",  # UBSan
    "Segmentation",
    "Stack dump",  # LLVM's crash handler
]

LOCATED_ERROR = re.compile(r"^[^\n:]+:\d+:\d+: error: ", re.MULTILINE)

TOKEN = re.compile(
    r"""(?P<comment>//[^\n]*|/\*.*?\*/)
      |(?P<string>"(?:[^"\\\n]|\\.)*")
      |(?P<number>\d+(?:\.\d*)?(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)
      |(?P<ident>[A-Za-z_]\w*|'[^'\n]*')
      |(?P<op>==|<>|<=|>=|:=|\.\^|\.\*|\./|\.\+|\.-|[-+*/^=<>()\[\]{};,.:])
      |(?P<space>\s+)
      |(?P<other>.)""",
    re.VERBOSE | re.DOTALL,
)

KEYWORDS = {
    "model", "end", "equation", "initial", "algorithm", "parameter",
    "constant", "Real", "Integer", "Boolean", "String", "der", "for", "in",
    "loop", "if", "then", "else", "elseif", "when", "connect", "extends",
    "function", "input", "output", "flow", "package", "import", "connector",
    "record", "type", "partial", "each", "final", "annotation", "true",
    "false", "and", "or", "not", "time", "fixed", "start", "nominal",
    "protected", "public", "within", "block", "discrete", "pre", "reinit",
}

NUMBERS = ["0", "1", "-1", "1e308", "-1e308", "1e-308", "1e309", "NaN",
           "(0/0)", "2147483648"]
OP_SWAPS = {"+": "-", "-": "+", "*": "/", "/": "*", "=": "==", "==": "="}
BAD_UTF8 = ["\udcff", "\udcc3(", "\udced\udca0\udc80", "\udc80", "\udcfe\udcfe"]


def tokenize(text):
    return [(m.lastgroup, m.group()) for m in TOKEN.finditer(text)]


def untokenize(tokens):
    return "".join(t for _, t in tokens)


# Each mutation takes (rng, text) and returns the new text, or None when it
# does not apply to this text (the caller then picks another).

def replace_token(rng, text, wanted, replacement):
    """Replaces one token (kind, text) for which wanted() holds by
    replacement(its text); None when there is none."""
    toks = tokenize(text)
    idx = [i for i, tok in enumerate(toks) if wanted(*tok)]
    if not idx:
        return None
    i = rng.choice(idx)
    toks[i] = (toks[i][0], replacement(toks[i][1]))
    return untokenize(toks)


def mut_number(rng, text):
    return replace_token(rng, text, lambda k, t: k == "number",
                         lambda t: rng.choice(NUMBERS))


def mut_operator(rng, text):
    return replace_token(rng, text, lambda k, t: k == "op" and t in OP_SWAPS,
                         lambda t: OP_SWAPS[t])


def statement_lines(lines):
    return [i for i, l in enumerate(lines)
            if "=" in l and l.rstrip().endswith(";") and not l.lstrip().startswith("//")]


def mut_equation_line(rng, text, duplicate):
    lines = text.split("\n")
    idx = statement_lines(lines)
    if not idx:
        return None
    i = rng.choice(idx)
    if duplicate:
        lines.insert(i, lines[i])
    else:
        del lines[i]
    return "\n".join(lines)


def mut_dup_equation(rng, text):
    return mut_equation_line(rng, text, duplicate=True)


def mut_del_equation(rng, text):
    return mut_equation_line(rng, text, duplicate=False)


DER = re.compile(r"der\(([^()]*)\)")


def pick_match(rng, pattern, text):
    ms = list(pattern.finditer(text))
    return rng.choice(ms) if ms else None


def mut_der(rng, text):
    m = pick_match(rng, DER, text)
    if not m:
        return None
    return text[: m.start()] + "der(der(" + m.group(1) + "))" + text[m.end():]


FIXED = re.compile(r"fixed\s*=\s*(true|false)")


def mut_fixed(rng, text):
    m = pick_match(rng, FIXED, text)
    if not m:
        return None
    if rng.random() < 0.5:
        new = "fixed = " + ("false" if m.group(1) == "true" else "true")
        return text[: m.start()] + new + text[m.end():]
    return remove_modifier(text, m.start(), m.end())


START = re.compile(r"start\s*=\s*[^,()]+(?:\([^()]*\))?")


def mut_start(rng, text):
    m = pick_match(rng, START, text)
    return m and remove_modifier(text, m.start(), m.end())


def remove_modifier(text, begin, end):
    """Removes text[begin:end] with one adjacent comma, so that
    `(start = 1, fixed = true)` becomes `(start = 1)`."""
    after = text[end:]
    stripped = after.lstrip()
    if stripped.startswith(","):
        return text[:begin] + stripped[1:].lstrip()
    before = text[:begin].rstrip()
    if before.endswith(","):
        return before[:-1] + after
    return text[:begin] + after


def mut_rename(rng, text):
    toks = tokenize(text)
    names = sorted({t for k, t in toks if k == "ident" and t not in KEYWORDS})
    if not names:
        return None
    old = rng.choice(names)
    new = rng.choice(names + ["zz", "x", "der", "time", "end"])
    everywhere = rng.random() < 0.5
    idx = [i for i, (k, t) in enumerate(toks) if k == "ident" and t == old]
    for i in idx if everywhere else [rng.choice(idx)]:
        toks[i] = ("ident", new)
    return untokenize(toks)


def mut_del_line(rng, text):
    lines = text.split("\n")
    if len(lines) < 2:
        return None
    del lines[rng.randrange(len(lines))]
    return "\n".join(lines)


def mut_bad_utf8(rng, text):
    at = rng.randrange(len(text) + 1)
    return text[:at] + rng.choice(BAD_UTF8) + text[at:]


def mut_truncate(rng, text):
    if not text:
        return None
    return text[: rng.randrange(len(text))]


MUTATIONS = [
    ("number", mut_number, 3),
    ("operator", mut_operator, 3),
    ("dup-equation", mut_dup_equation, 2),
    ("del-equation", mut_del_equation, 2),
    ("der", mut_der, 2),
    ("fixed", mut_fixed, 1),
    ("start", mut_start, 1),
    ("rename", mut_rename, 2),
    ("del-line", mut_del_line, 2),
    ("bad-utf8", mut_bad_utf8, 1),
    ("truncate", mut_truncate, 1),
]


def read_corpus(source_dir):
    corpus = []
    for top in ("examples", "tests", "stdlib"):
        for root, dirs, files in os.walk(os.path.join(source_dir, top)):
            dirs.sort()
            for f in sorted(files):
                if f.endswith(".lsd"):
                    path = os.path.join(root, f)
                    with open(path, "rb") as fh:
                        text = fh.read().decode("utf-8", "surrogateescape")
                    if "--limit-as" in text:
                        continue  # made to run out of memory: slow, not a seed
                    corpus.append((os.path.relpath(path, source_dir), text))
    return corpus


MODEL_OPTION = re.compile(r"--model\s+([A-Za-z_]\w*)")


# Files that hold working models are picked more often than the error
# tests, so more mutants get past the frontend into the later stages.
RICH_DIRS = ("examples/", "tests/models/", "tests/lang/analysis/",
             "tests/lang/models/")


def weight(origin):
    return 3 if origin.startswith(RICH_DIRS) else 1


def make_mutant(corpus, seed, k):
    """Mutant k of `seed`: (origin, mutations, text, model name or None)."""
    rng = random.Random(seed * 1_000_003 + k)
    origin, text = rng.choices(corpus, [weight(o) for o, _ in corpus])[0]
    weights = [w for _, _, w in MUTATIONS]
    applied = []
    for _ in range(rng.choice([1, 1, 2, 3])):
        for _attempt in range(8):
            name, fn, _ = rng.choices(MUTATIONS, weights)[0]
            new = fn(rng, text)
            if new is not None and new != text:
                text = new
                applied.append(name)
                break
    # Language tests select models with --model in their RUN lines; use one
    # of them half of the time, while the mutant still declares it.
    model = None
    names = sorted(set(MODEL_OPTION.findall(corpus_text(corpus, origin))))
    if names and rng.random() < 0.5:
        name = rng.choice(names)
        if re.search(r"\b(model|block|class)\s+" + name + r"\b", text):
            model = name
    return origin, applied, text, model


def corpus_text(corpus, origin):
    for o, t in corpus:
        if o == origin:
            return t
    return ""


def limit_resources(mem_bytes, cpu_seconds):
    """A stage run's limits: memory (0: none) and CPU time. CPU time, not
    wall time, decides a hang: on a machine busy with other work a stage
    run waits for a core without using its limit (mutant 341, w = 1e7 for
    0.1 s, 4.2 s of CPU, timed out at 10 s of wall time beside a build)."""
    def apply():
        if mem_bytes:
            resource.setrlimit(resource.RLIMIT_AS, (mem_bytes, mem_bytes))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        cpu = int(math.ceil(cpu_seconds))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 5))
    return apply


def wall_backstop(cpu_seconds):
    """Wall time after which a stage run that uses no CPU (blocked on a
    read) counts as hung: far beyond any wait for a core."""
    return max(300.0, 30 * cpu_seconds)


def classify(rc, stderr, timed_out):
    """The failure kind of one stage run, or None when it ended properly."""
    if timed_out or rc == -signal.SIGXCPU or rc == -signal.SIGKILL:
        return "hang"  # the CPU-time limit (SIGXCPU, then SIGKILL)
    if rc < 0:
        return "crash"
    for text in ABORT_TEXTS:
        if text in stderr:
            return "crash"
    if rc not in (0, 1, 2, 3):
        return "crash"
    if rc == 1 and not LOCATED_ERROR.search(stderr):
        return "unlocated"
    return None


def signature(kind, stage, err):
    """A failure's kind and first telling stderr line, names and numbers
    blanked, so the same bug found by many mutants counts once."""
    lines = err.splitlines()
    tell = next((l for l in lines if any(t in l for t in ABORT_TEXTS)),
                lines[0] if lines else "(no output)")
    if not any(t in tell for t in ABORT_TEXTS):
        tell = re.sub(r"'[^']*'", "'_'", tell)
    tell = re.sub(r"\b\d+\b", "N", tell)
    tell = re.sub(r"/\S+/m\d+\.lsd", "M.lsd", tell)
    return "%s %s: %s" % (kind, stage, tell.strip()[:160])


# Worker state, set once per process by init_worker.
CONFIG = {}


def init_worker(config):
    CONFIG.update(config)


def run_mutant(k):
    cfg = CONFIG
    origin, applied, text, model = make_mutant(cfg["corpus"], cfg["seed"], k)
    mutant_dir = os.path.join(cfg["work_dir"], "mutants")
    path = os.path.join(mutant_dir, "m%06d.lsd" % k)
    with open(path, "wb") as fh:
        fh.write(text.encode("utf-8", "surrogateescape"))
    results = []
    keep = False
    for stage, args in STAGES:
        cmd = [cfg["ldaec"], path] + args
        if model:
            cmd += ["--model", model]
        if stage == "simulate":
            cmd += ["--jit", "on" if k % 4 == 3 else "off"]
        preexec = limit_resources(cfg["mem_bytes"], cfg["timeout"])
        timed_out = False
        start = time.monotonic()
        try:
            proc = subprocess.run(cmd, stdin=subprocess.DEVNULL,
                                  stdout=subprocess.DEVNULL,
                                  stderr=subprocess.PIPE,
                                  timeout=wall_backstop(cfg["timeout"]),
                                  preexec_fn=preexec)
            rc, err = proc.returncode, proc.stderr
        except subprocess.TimeoutExpired as e:
            rc, err, timed_out = None, e.stderr or b"", True
        seconds = time.monotonic() - start
        err = err.decode("utf-8", "replace")
        kind = classify(rc, err, timed_out)
        if kind:
            keep = True
        results.append((stage, rc, kind, cmd, err[-3000:], seconds))
    if not keep:
        os.remove(path)
    return k, origin, applied, model, text, results


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", required=True, help="the ldaec binary")
    ap.add_argument("--source-dir", default=os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", ".."),
        help="repository root (the .lsd files are read from it)")
    ap.add_argument("--work-dir", required=True,
                    help="where mutants that fail are kept (reproducers)")
    ap.add_argument("--count", type=int, default=2000,
                    help="stage runs (5 per mutant; default 2000)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=10.0,
                    help="CPU seconds per stage run")
    ap.add_argument("--mem-gb", type=float, default=3.0,
                    help="address-space cap per stage run (0: none; "
                    "sanitizer builds need 0)")
    ap.add_argument("--first", type=int, default=0,
                    help="index of the first mutant (to re-run one: "
                    "--first K --count 5)")
    opts = ap.parse_args()

    corpus = read_corpus(os.path.abspath(opts.source_dir))
    if not corpus:
        print("no .lsd files under", opts.source_dir)
        return 2
    os.makedirs(os.path.join(opts.work_dir, "mutants"), exist_ok=True)
    config = {
        "corpus": corpus, "seed": opts.seed, "ldaec": opts.ldaec,
        "work_dir": opts.work_dir, "timeout": opts.timeout,
        "mem_bytes": int(opts.mem_gb * (1 << 30)),
    }
    mutants = range(opts.first,
                    opts.first + max(1, -(-opts.count // len(STAGES))))
    print("mutation test: %d files, %d mutants x %d stages, seed %d, %d jobs"
          % (len(corpus), len(mutants), len(STAGES), opts.seed, opts.jobs),
          flush=True)

    counts = collections.Counter()
    by_exit = collections.Counter()
    by_stage_time = collections.defaultdict(float)
    failures = {}  # mutant -> (origin, mutations, text, failed stages)
    started = time.monotonic()
    ctx = multiprocessing.get_context("fork")
    with ctx.Pool(opts.jobs, initializer=init_worker,
                  initargs=(config,)) as pool:
        for k, origin, applied, model, text, results in pool.imap(
                run_mutant, mutants, chunksize=4):
            for stage, rc, kind, cmd, err, seconds in results:
                counts["runs"] += 1
                if counts["runs"] % 10000 == 0:
                    print("... %d stage runs, %d failed, %.0f s"
                          % (counts["runs"], len(failures),
                             time.monotonic() - started), flush=True)
                by_exit["timeout" if rc is None else rc] += 1
                by_stage_time[stage] += seconds
                if kind:
                    counts[kind] += 1
                    failures.setdefault(k, (origin, applied, text, []))[3].append(
                        (stage, rc, kind, cmd, err))
    elapsed = time.monotonic() - started

    signatures = collections.Counter()
    for k, (origin, applied, text, stages) in sorted(failures.items()):
        print("\n=== FAIL mutant %d of %s [%s]" % (k, origin, ", ".join(applied)))
        if len(text) <= 2000:
            print("--- mutant ---")
            print(text.encode("utf-8", "surrogateescape").decode(
                "utf-8", "replace").rstrip())
        for stage, rc, kind, cmd, err in stages:
            signatures[signature(kind, stage, err)] += 1
            print("--- %s, stage %s, exit %s; reproducer:" % (kind, stage, rc))
            print(" ".join(cmd))
            print(err.rstrip()[-1500:])
    if signatures:
        print("\ndistinct failures (stage runs):")
        for sig, n in signatures.most_common():
            print("  %5d  %s" % (n, sig))
    print("\ntime: %.1f s (%s)" % (elapsed, ", ".join(
        "%s %.1f s" % (s, by_stage_time[s]) for s, _ in STAGES)))
    exits = {str(c): n for c, n in sorted(by_exit.items(), key=str)}
    print("stage runs: %d, crashes: %d, hangs: %d, unlocated model errors: "
          "%d, by exit code: %s" % (counts["runs"], counts["crash"],
                                    counts["hang"], counts["unlocated"],
                                    exits))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
