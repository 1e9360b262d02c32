#!/usr/bin/env python3
"""The JIT object cache as a trust boundary (docs/codegen.md, "Threat
model"): entries are machine code ldaec runs, so nothing another user could
have written is loaded. Each case plants something in a cache directory and
checks that the run compiles instead (--stats says "object cache: miss"),
writes the right numbers, and never hangs.

Usage: check_cache_trust.py LDAEC WORKDIR. Standard library only; the cases
that need another user (chown) run as root only.
"""
import hashlib
import os
import pwd
import resource
import shutil
import stat
import struct
import subprocess
import sys
import time

LDAEC, WORK = sys.argv[1], sys.argv[2]
MAGIC = b"LDAEOBJ2"
failures = []

MODEL_A = """model A
  Real x(start = 1, fixed = true);
equation
  der(x) = -2 * x;
end A;
"""
# Another model whose object, planted under A's key, would give other
# numbers (x grows) with exit 0.
MODEL_B = """model A
  Real x(start = 1, fixed = true);
equation
  der(x) = 3 * x + 1;
end A;
"""


def check(ok, what):
    print(("ok:   " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


def cpu_limit():
    resource.setrlimit(resource.RLIMIT_CPU, (60, 65))


def run(model, cache, extra=()):
    """(stdout CSV, stderr) of a --jit on run of `model` with the cache."""
    env = dict(os.environ, LDAEC_CACHE_DIR=cache)
    p = subprocess.run([LDAEC, model, "--simulate", "--jit", "on", "--stats",
                        "--stop", "1", "--output-times", "1", "--no-progress",
                        *extra],
                       capture_output=True, text=True, env=env,
                       preexec_fn=cpu_limit, timeout=300)
    if p.returncode != 0:
        print(p.stderr)
    return p.stdout, p.stderr


def x_at_1(csv):
    return float(csv.strip().splitlines()[-1].split(",")[1])


def entries(cache):
    return [f for f in os.listdir(cache) if f.endswith(".ldaeobj")]


def forge(cache, key, obj, mode=0o600):
    """A whole, valid entry for `key` holding `obj`: what an attacker who
    can write the directory would plant (the SHA-256 is no secret)."""
    path = os.path.join(cache, key + ".ldaeobj")
    header = MAGIC + struct.pack("<Q", len(obj)) + hashlib.sha256(obj).digest()
    with open(path, "wb") as f:
        f.write(header + key.encode())
        f.write(obj)
    os.chmod(path, mode)
    return path


def fresh(name, mode=0o700):
    d = os.path.join(WORK, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    os.chmod(d, mode)
    return d


os.makedirs(WORK, exist_ok=True)
model_a = os.path.join(WORK, "a.lsd")
model_b = os.path.join(WORK, "b.lsd")
open(model_a, "w").write(MODEL_A)
open(model_b, "w").write(MODEL_B)
right = 0.1353352832366127  # exp(-2)

# The object of B and the key of A, from their own private caches.
cache_b = fresh("b")
run(model_b, cache_b)
(entry_b,) = entries(cache_b)
obj_b = open(os.path.join(cache_b, entry_b), "rb").read()[112:]
cache_a = fresh("a")
out, _ = run(model_a, cache_a)
check(abs(x_at_1(out) - right) < 1e-5, "model A compiled: x(1) = exp(-2)")
(entry_a,) = entries(cache_a)
key_a = entry_a[:-len(".ldaeobj")]

# A new cache directory is created private.
new = os.path.join(WORK, "new", "sub")
shutil.rmtree(os.path.join(WORK, "new"), ignore_errors=True)
run(model_a, new)
check(stat.S_IMODE(os.stat(new).st_mode) == 0o700,
      "a cache directory ldaec creates is 0700 (%o)"
      % stat.S_IMODE(os.stat(new).st_mode))

# Control: B's object forged under A's key in the user's own private cache
# is loaded (the user trusts what they wrote): the planted code runs.
own = fresh("own")
forge(own, key_a, obj_b)
out, err = run(model_a, own)
check("object cache: hit" in err and abs(x_at_1(out) - right) > 1,
      "control: a valid entry of the user's own, 0600, is loaded")


def planted_is_ignored(what, cache, path=None, warned=None):
    out, err = run(model_a, cache)
    ok = "object cache: hit" not in err and abs(x_at_1(out) - right) < 1e-5
    if warned:
        ok = ok and warned in err
    check(ok, what)


# An entry with a valid xxh3 checksum of the old layout, or any digest
# that is not the object's SHA-256: rejected.
d = fresh("digest")
p = forge(d, key_a, obj_b)
data = bytearray(open(p, "rb").read())
data[16:48] = bytes(32)
open(p, "wb").write(bytes(data))
planted_is_ignored("an entry whose SHA-256 does not match is not loaded", d)

# A whole valid entry that others could have written: not loaded.
d = fresh("writable_entry")
forge(d, key_a, obj_b, mode=0o666)
planted_is_ignored("an entry writable by others is not loaded", d)

# A directory others can write: not used at all, a warning, nothing written.
d = fresh("open_dir", mode=0o777)
os.chmod(d, 0o777)
forge(d, key_a, obj_b)
planted_is_ignored("a directory writable by others is not used (warning)", d,
                   warned="other users can write to it")
check(len(entries(d)) == 1, "nothing written to a directory others can write")

# A symbolic link as the directory: not used.
target = fresh("link_target")
forge(target, key_a, obj_b)
link = os.path.join(WORK, "link_dir")
if os.path.lexists(link):
    os.remove(link)
os.symlink(target, link)
planted_is_ignored("a cache directory that is a symbolic link is not used",
                   link, warned="it is a symbolic link")

# A FIFO in an entry's place: no hang; a symlink to /dev/zero: no
# "out of memory".
d = fresh("fifo")
os.mkfifo(os.path.join(d, key_a + ".ldaeobj"))
t0 = time.monotonic()
planted_is_ignored("a FIFO entry is skipped", d)
check(time.monotonic() - t0 < 120, "... without waiting on it")
d = fresh("zero")
os.symlink("/dev/zero", os.path.join(d, key_a + ".ldaeobj"))
planted_is_ignored("a symbolic link entry (to /dev/zero) is skipped", d)

# Another user's entry, or directory: only root can make them here.
if os.geteuid() == 0:
    nobody = pwd.getpwnam("nobody").pw_uid
    d = fresh("other_entry")
    os.chown(forge(d, key_a, obj_b), nobody, -1)
    planted_is_ignored("an entry owned by another user is not loaded", d)
    d = fresh("other_dir")
    forge(d, key_a, obj_b)
    os.chown(d, nobody, -1)
    planted_is_ignored("a directory owned by another user is not used", d,
                       warned="it is owned by another user")
else:
    print("skip: another user's entry and directory (needs root)")

# The trim removes only the cache's own files: an old foreign *.tmp stays,
# an old temporary file of the cache's own naming goes.
d = fresh("trim")
old = time.time() - 3 * 86400
thesis = os.path.join(d, "thesis.tmp")
own_tmp = os.path.join(d, "." + "0" * 64 + ".123.456.tmp")
for f in (thesis, own_tmp):
    open(f, "w").write("x")
    os.chmod(f, 0o600)
    os.utime(f, (old, old))
run(model_a, d)
check(os.path.exists(thesis), "the trim leaves a foreign thesis.tmp alone")
check(not os.path.exists(own_tmp), "the trim removes its own stale temporary")

print("all passed" if not failures else "%d failed" % len(failures))
sys.exit(1 if failures else 0)
