#!/usr/bin/env python3
"""Checks that the SUNDIALS code ldaec runs is the -O2 build of
scripts/build-sundials.sh, not Debian's -O0 libsundials-dev
(docs/sundials.md).

  check_sundials.py ldd FILE
      FILE loads no libsundials shared library from /usr/lib or /lib
      (with the static build it loads none at all).
  check_sundials.py optimized FILE [SYMBOL ...]
      The machine code of each SUNDIALS function (by default one from each
      library the runtime links, those FILE links at all) is not -O0 code. The function is looked
      for in FILE, then in the shared libraries FILE loads, so a binary
      linked against Debian's libraries fails too.

-O0 code is recognised by what gcc and clang do without optimization: set
up a frame pointer (push %rbp; mov %rsp,%rbp) and store the incoming
argument registers to stack slots below it (mov %rdi,-0x38(%rbp)), then
reload every local from its slot. Optimized x86-64 code omits the frame
pointer and keeps arguments in registers.
"""
import os
import re
import shutil
import subprocess
import sys

# One function from each SUNDIALS library the runtime links.
DEFAULT_SYMBOLS = [
    "N_VWSqrSumLocal_Serial",  # nvecserial: the WRMS-norm kernel
    "N_VLinearSum_Serial",     # nvecserial
    "SUNMatMatvec_Dense",      # sunmatrixdense
    "SUNMatMatvec_Sparse",     # sunmatrixsparse
    "SUNDlsMat_denseGETRF",    # the LU the dense linear solver calls
    "SUNLinSolSolve_KLU",      # sunlinsolklu
    "IDASolve",                # ida
    "CVode",                   # cvode
]

# Every user of the runtime links these: the vector kernel and IDA.
REQUIRED_SYMBOLS = {"N_VWSqrSumLocal_Serial", "IDASolve"}

ARG_REGS = r"%(?:rdi|rsi|rdx|rcx|r8|r9|edi|esi|edx|ecx|r8d|r9d|xmm[0-7])"
ARG_SPILL = re.compile(r"\bmov\w*\s+" + ARG_REGS + r",-0x[0-9a-f]+\(%rbp\)")
FRAME_SETUP = re.compile(r"\bmov\s+%rsp,%rbp\b")
FRAME_SLOT = re.compile(r"-0x[0-9a-f]+\(%rbp\)")
SYSTEM_LIB_DIRS = ("/usr/lib", "/lib")


def shared_libraries(path):
    """(name, resolved path) of every shared library `ldd` lists."""
    out = subprocess.run(["ldd", path], capture_output=True, text=True)
    libs = []
    for line in out.stdout.splitlines():
        m = re.match(r"\s*(\S+)\s+=>\s+(\S+)", line)
        if m:
            libs.append((m.group(1), m.group(2)))
    return libs


def check_ldd(path):
    libs = [(n, p) for n, p in shared_libraries(path) if "libsundials" in n]
    for name, where in libs:
        print(f"{path} loads {name} from {where}")
    bad = [p for _, p in libs if p.startswith(SYSTEM_LIB_DIRS)]
    if bad:
        print("FAIL: SUNDIALS from the system (Debian's -O0 build): "
              + ", ".join(bad))
        return 1
    if not libs:
        print(f"ok: {path} loads no libsundials shared library (static)")
    else:
        print("ok: no libsundials from /usr/lib or /lib")
    return 0


def objdump():
    for tool in ("objdump", "llvm-objdump-19", "llvm-objdump"):
        if shutil.which(tool):
            return tool
    sys.exit("no objdump on PATH (binutils or llvm-19-tools)")


def disassemble(tool, path, symbol):
    """Instruction lines of `symbol` in `path`, or [] when not defined there."""
    out = subprocess.run([tool, "-d", "--no-show-raw-insn",
                          f"--disassemble={symbol}", path],
                         capture_output=True, text=True).stdout
    lines, inside = [], False
    for line in out.splitlines():
        # "<sym>:" or, in a versioned shared library, "<sym@@Base>:"
        if re.search(r"<" + re.escape(symbol) + r"(@@?\w+)?>:$", line):
            inside = True
        elif inside and line.strip() and re.match(r"\s*[0-9a-f]+:\s", line):
            lines.append(line)
        elif inside and not line.strip():
            break
    return lines


def check_optimized(path, symbols, required):
    """Every symbol found must be optimized code; those in `required`
    must be found. A static link leaves out what nothing calls (CVODE
    before the runtime used it), so the others may be absent."""
    tool = objdump()
    places = [path] + [p for _, p in shared_libraries(path)]
    failed = checked = 0
    for symbol in symbols:
        for place in places:
            code = disassemble(tool, place, symbol)
            if code:
                break
        if not code:
            if symbol in required:
                print(f"FAIL: {symbol} not found in {path} or the libraries it loads")
                failed += 1
            else:
                print(f"{symbol}: not linked")
            continue
        checked += 1
        text = "\n".join(code)
        frame = bool(FRAME_SETUP.search(text))
        spills = ARG_SPILL.findall(text)
        slots = len(FRAME_SLOT.findall(text))
        where = "" if place == path else f" (in {place})"
        print(f"{symbol}{where}: {len(code)} instructions, frame pointer "
              f"{'set up' if frame else 'omitted'}, {len(spills)} stores of "
              f"argument registers to the frame, {slots} frame-slot accesses")
        if frame and spills:
            print(f"FAIL: {symbol} is unoptimized (-O0) code: arguments "
                  f"stored to the stack, e.g. '{spills[0]}'")
            failed += 1
    if failed:
        return 1
    print(f"ok: {checked} SUNDIALS functions are optimized code")
    return 0


def main(argv):
    if len(argv) < 3 or argv[1] not in ("ldd", "optimized"):
        print(__doc__, file=sys.stderr)
        return 2
    path = argv[2]
    if not os.path.exists(path):
        print(f"no such file: {path}", file=sys.stderr)
        return 2
    if argv[1] == "ldd":
        return check_ldd(path)
    if argv[3:]:
        return check_optimized(path, argv[3:], set(argv[3:]))
    return check_optimized(path, DEFAULT_SYMBOLS, REQUIRED_SYMBOLS)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
