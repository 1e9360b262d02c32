# Runs the command given as arguments, passes its stdout and stderr through
# (stderr first, so messages come before results), then prints
# "exit code: N": the language tests check exact exit codes with it (lit's
# `not` only says nonzero). With `--limit-as MB` first, the command's
# address space is limited to MB megabytes (to test running out of
# memory). Always exits 0 itself.
import resource
import subprocess
import sys

args = sys.argv[1:]
limit = None
if args[:1] == ["--limit-as"]:
    limit = int(args[1]) * 1024 * 1024
    args = args[2:]


def apply_limit():
    if limit is not None:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


proc = subprocess.run(args, capture_output=True, preexec_fn=apply_limit)
sys.stdout.buffer.write(proc.stderr)
sys.stdout.buffer.write(proc.stdout)
sys.stdout.write("exit code: %d\n" % proc.returncode)
