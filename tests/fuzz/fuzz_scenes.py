#!/usr/bin/python3
"""Bounded, deterministic fuzz run of scene files (docs/input_errors.md, "Fuzzing").

Mutates the shipped scenes (parameters/*.prm, benchmarks/*/*.prm; not the study files
of parameters/studies and parameters/calibration) and runs `suturesim --validate` on
each mutant. Every valid mutant of a realtime scene (top level Model = realtime)
or a suture-only one (Bodies = suture) also gets a short run: --set "Time/End time=0.01"
(suture-only: and the step size, one step); the accurate FE scenes are too slow for it.
Case i is a function of the seed, i and the source scenes alone, so a run of N cases is
a prefix of a run of more, whatever the machine's speed.

Verdicts:
  exit 0                    fine (--validate: '<mutant>: valid' on stdout)
  exit 2                    fine if the output is exactly one line, on stderr, starting
                            'error: ' and naming the mutant as '<mutant>:<line>:' or
                            '<mutant>: <Parameter/path> (default):' (or '<mutant>: ' for
                            a mutant without any setting line: it has no line to name),
                            or an option ('error: --set ...'); otherwise a failure
  exit 3                    fine for a short run (a solve failed) with one 'error: '
                            line on stderr; a failure for --validate
  exit 6                    fine for a short run (it ended without what its scene asked
                            for) with one 'incomplete: ' line on stderr
  anything else             a failure: exit 4 (internal error), 1 (sanitizer), a signal,
                            a timeout, a sanitizer report in any case
Failures are printed and their mutants kept in <work>/failures/. Exit status: 0 when
there is none, 1 otherwise.

Standard library only; run with /usr/bin/python3.
"""

import argparse
import collections
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

DEFAULT_SEED = 20240611

HOSTILE = [
    b"",
    b"-1",
    b"0",
    b"-0",
    b"1e308",
    b"-1e308",
    b"4.9e-324",
    b"1e-300",
    b"nan",
    b"inf",
    b"-inf",
    b"1e999",
    b"99999999999",
    b"-99999999999",
    b"0x10",
    b"text",
    b"x" * 5000,
    b"9" * 70000,  # a line above the 65 536-character limit
    b"\xff\xfe\xc3(",  # not UTF-8
    b"caf\xe9",  # Latin-1, not UTF-8
    b"'\"; $(touch fuzz_pwned) `id`",
    b"1, 2",
    b", , ,",
    b"a: b: c;;",
    b"=",
    b"\\",
]

SANITIZER_MARKS = (
    "ERROR: AddressSanitizer",
    "ERROR: LeakSanitizer",
    "runtime error:",
    "SUMMARY: UndefinedBehaviorSanitizer",
    "SUMMARY: AddressSanitizer",
)

SET_LINE = re.compile(rb"^(\s*set\s+[^=]*=)(.*)$", re.IGNORECASE)
END_LINE = re.compile(rb"^\s*end\s*(#.*)?$", re.IGNORECASE)


# --- sources ------------------------------------------------------------------------

def default_sources(root):
    """The shipped scenes: parameters/*.prm (not its studies/, calibration/ folders) and
    benchmarks/<case>/*.prm."""
    files = sorted((root / "parameters").glob("*.prm"))
    files += sorted((root / "benchmarks").glob("*/*.prm"))
    return [f for f in files if f.parent.name not in ("studies", "calibration")]


def short_run_kind(text):
    """'realtime' for a scene whose top level sets Model = realtime, 'suture' for a
    suture-only one (Bodies = suture: a rod, fast on either path), None otherwise (an
    accurate FE scene: seconds to minutes per step, too slow for a short run, most of
    all under the sanitizers)."""
    depth = 0
    kind = None
    for raw in text.splitlines():
        line = raw.split(b"#", 1)[0].strip()
        low = line.lower()
        if low.startswith(b"subsection"):
            depth += 1
        elif low == b"end":
            depth -= 1
        elif depth == 0:
            m = re.match(rb"set\s+(model|bodies)\s*=\s*(.*)$", line, re.IGNORECASE)
            if m and m.group(1).lower() == b"model" and m.group(2).strip() == b"realtime":
                kind = "realtime"
            if m and m.group(1).lower() == b"bodies" and m.group(2).strip() == b"suture" and kind is None:
                kind = "suture"
    return kind


# --- mutations ----------------------------------------------------------------------

def lines_of(data):
    return data.split(b"\n")


def content_lines(lines):
    """Indices of lines that are not blank or only a comment."""
    out = [i for i, l in enumerate(lines) if l.strip() and not l.strip().startswith(b"#")]
    return out or list(range(len(lines)))


def keys_of(lines):
    keys = []
    for l in lines:
        m = re.match(rb"^\s*set\s+([^=]*?)\s*=", l, re.IGNORECASE)
        if m:
            keys.append(m.group(1))
    return keys


def random_line(rng, lines, pattern):
    """The index of a random line matching pattern, None when none does."""
    matching = [i for i, l in enumerate(lines) if pattern.match(l)]
    return rng.choice(matching) if matching else None


def mutate_replace_value(rng, data):
    lines = lines_of(data)
    i = random_line(rng, lines, SET_LINE)
    if i is None:
        return None
    head, value = SET_LINE.match(lines[i]).groups()
    value = value.split(b"#", 1)[0]
    hostile = rng.choice(HOSTILE)
    items = value.split(b",")
    if len(items) > 1 and rng.random() < 0.5:
        k = rng.randrange(len(items))
        items[k] = b" " + hostile
        new = b",".join(items)
        what = "item %d of the value" % (k + 1)
    else:
        new = b" " + hostile
        what = "value"
    lines[i] = head + new
    return b"\n".join(lines), "replace %s on line %d by %s" % (what, i + 1, show(hostile))


def mutate_delete_line(rng, data):
    lines = lines_of(data)
    i = rng.choice(content_lines(lines))
    del lines[i]
    return b"\n".join(lines), "delete line %d" % (i + 1)


def mutate_duplicate_line(rng, data):
    lines = lines_of(data)
    i = rng.choice(content_lines(lines))
    lines.insert(i, lines[i])
    return b"\n".join(lines), "duplicate line %d" % (i + 1)


def mutate_swap_lines(rng, data):
    lines = lines_of(data)
    c = content_lines(lines)
    if len(c) < 2:
        return None
    i, j = sorted(rng.sample(c, 2))
    lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines), "swap lines %d and %d" % (i + 1, j + 1)


def mutate_truncate(rng, data):
    n = rng.randrange(len(data)) if data else 0
    return data[:n], "truncate at byte %d of %d" % (n, len(data))


def mutate_insert(rng, data):
    lines = lines_of(data)
    i = rng.randrange(len(lines) + 1)
    choice = rng.randrange(4)
    if choice == 0:  # a key of the file (at any depth), a hostile value
        keys = keys_of(lines) or [b"Scene name"]
        new = [b"set " + rng.choice(keys) + b" = " + rng.choice(HOSTILE)]
    elif choice == 1:  # a key of the file, a value of another line of the file
        keys = keys_of(lines) or [b"Scene name"]
        values = [SET_LINE.match(l).group(2).strip() for l in lines if SET_LINE.match(l)] or [b"1"]
        new = [b"set " + rng.choice(keys) + b" = " + rng.choice(values)]
    elif choice == 2:  # an unknown key
        new = [b"set Fuzz key %d = %s" % (rng.randrange(1000), rng.choice(HOSTILE))]
    else:  # an unknown subsection, closed or not
        new = [b"subsection Fuzz section %d" % rng.randrange(1000)]
        if rng.random() < 0.5:
            new += [b"  set Anything = 1", b"end"]
    lines[i:i] = new
    return b"\n".join(lines), "insert %s before line %d" % (show(b" / ".join(new)), i + 1)


def mutate_flip_byte(rng, data):
    if not data:
        return None
    b = bytearray(data)
    i = rng.randrange(len(b))
    old = b[i]
    if rng.random() < 0.5:
        b[i] ^= 1 << rng.randrange(8)
    else:
        b[i] = rng.randrange(256)
    return bytes(b), "byte %d: 0x%02x -> 0x%02x" % (i, old, b[i])


def mutate_drop_end(rng, data):
    lines = lines_of(data)
    i = random_line(rng, lines, END_LINE)
    if i is None:
        return None
    del lines[i]
    return b"\n".join(lines), "drop the 'end' of line %d" % (i + 1)


MUTATIONS = [  # (weight, function)
    (6, mutate_replace_value),
    (2, mutate_delete_line),
    (1, mutate_duplicate_line),
    (1, mutate_swap_lines),
    (1, mutate_truncate),
    (2, mutate_insert),
    (1, mutate_flip_byte),
    (1, mutate_drop_end),
]


def show(b, limit=60):
    text = repr(b)[2:-1]
    return "'" + (text if len(text) <= limit else text[:limit] + "...(%d bytes)" % len(b)) + "'"


def make_case(seed, index, sources):
    """Case @p index of @p seed: (source index, mutant bytes, description), from its own
    random.Random so that it depends on nothing else."""
    rng = random.Random("%d/%d" % (seed, index))
    s = rng.randrange(len(sources))
    data = sources[s][1]
    count = 1 if rng.random() < 0.75 else rng.choice((2, 3))
    done = []
    weights = [w for w, _ in MUTATIONS]
    functions = [f for _, f in MUTATIONS]
    while len(done) < count:
        f = rng.choices(functions, weights)[0]
        result = f(rng, data)
        if result is None:
            continue
        data, what = result
        done.append(what)
    return s, data, "; ".join(done)


# --- running ------------------------------------------------------------------------

def run(command, cwd, timeout, env):
    """(return code or 'timeout', stdout, stderr, seconds); the process group is killed on
    a timeout."""
    start = time.monotonic()
    p = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         stdin=subprocess.DEVNULL, start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
        code = p.returncode
    except subprocess.TimeoutExpired:
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        out, err = p.communicate()
        code = "timeout"
    return code, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), time.monotonic() - start


def build_stamp(binary):
    """Times and sizes of @p binary and the project's libraries beside it: a rebuild
    during the run would void its results."""
    stamp = []
    for f in [binary] + sorted(binary.parent.glob("libsuturesim*.so*")):
        try:
            st = f.stat()
            stamp.append((str(f), st.st_mtime_ns, st.st_size))
        except OSError:
            stamp.append((str(f), None, None))
    return stamp


def nonempty(text):
    return [l for l in text.splitlines() if l.strip()]


def has_settings(data):
    """Whether @p data has a line other than blank ones and comments."""
    return any(l.strip() and not l.strip().startswith(b"#") for l in data.split(b"\n"))


def error_line_names_input(line, mutant, data):
    m = str(mutant)
    if line.startswith("error: " + m + ":"):
        rest = line[len("error: " + m + ":"):]
        if re.match(r"\d+: ", rest):
            return True  # <mutant>:<line>:
        if re.match(r" [^:]+ \(default\): ", rest):
            return True  # <mutant>: <Parameter/path> (default):
        # a file without a setting has no line to name: '<mutant>: <problem>'
        return not has_settings(data) and rest.startswith(" ")
    return re.match(r"error: --[a-z]", line) is not None


def verdict(kind, code, out, err, mutant, data):
    """None when the case passes, else the reason it fails."""
    for mark in SANITIZER_MARKS:
        if mark in out or mark in err:
            return "sanitizer report (%s)" % mark
    if code == "timeout":
        return "timeout (a hang?)"
    if code < 0:
        return "killed by signal %d" % -code
    if code == 0:
        if kind == "validate" and (str(mutant) + ": valid") not in out:
            return "exit 0 without '<file>: valid'"
        return None
    if code == 2 or (code == 3 and kind == "run"):
        lines = nonempty(err) + (nonempty(out) if kind == "validate" else [])
        if len(lines) != 1:
            return "exit %d with %d non-empty output lines (one 'error: ' line expected)" % (code, len(lines))
        if not lines[0].startswith("error: "):
            return "exit %d, the line does not start with 'error: '" % code
        if code == 2 and not error_line_names_input(lines[0], mutant, data):
            return "exit 2, the error line names neither '<file>:<line>:' nor an option"
        return None
    if code == 6 and kind == "run":
        lines = [l for l in nonempty(err) if not l.startswith("suturesim: ")]
        if len(lines) != 1 or not lines[0].startswith("incomplete: "):
            return "exit 6 without exactly one 'incomplete: ' line on stderr"
        return None
    if code == 3:
        return "exit 3 (solver failure) from --validate"
    if code == 4:
        return "exit 4 (internal error)"
    return "exit %d" % code


def main():
    here = Path(__file__).resolve().parent
    root = here.parent.parent
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--suturesim", required=True, help="the suturesim binary under test")
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED, help="default %(default)s")
    ap.add_argument("--cases", type=int, default=None, help="number of cases (default: until --budget)")
    ap.add_argument("--budget", type=float, default=None,
                    help="seconds; no new case starts after it (default: 120 without --cases)")
    ap.add_argument("--first", type=int, default=0, help="index of the first case (to reproduce one)")
    ap.add_argument("--work", required=True, help="scratch folder (its mutants/, runs/ and failures/ are cleared)")
    ap.add_argument("--sources", nargs="+", default=None, help="scenes to mutate (default: the shipped ones)")
    ap.add_argument("--short-run-every", type=int, default=1,
                    help="short run of every Nth valid mutant of a realtime or suture-only scene (0: none)")
    ap.add_argument("--end-time", type=float, default=0.01, help="short runs' Time/End time, s")
    ap.add_argument("--timeout", type=float, default=20, help="per --validate, s")
    ap.add_argument("--run-timeout", type=float, default=60, help="per short run, s")
    ap.add_argument("--keep", action="store_true", help="keep every mutant, not only the failing ones")
    ap.add_argument("--verbose", action="store_true", help="one line per case")
    args = ap.parse_args()
    if args.cases is None and args.budget is None:
        args.budget = 120.0

    binary = Path(args.suturesim).resolve()
    if not os.access(binary, os.X_OK):
        print("fuzz: %s is not an executable" % binary, file=sys.stderr)
        return 1
    stamp = build_stamp(binary)
    work = Path(args.work).resolve()
    for sub in ("mutants", "runs", "failures"):
        shutil.rmtree(work / sub, ignore_errors=True)
        (work / sub).mkdir(parents=True)
    if (work / "fuzz_pwned").exists():
        (work / "fuzz_pwned").unlink()
    paths = [Path(p).resolve() for p in args.sources] if args.sources else default_sources(root)
    sources = [(p, p.read_bytes()) for p in paths]
    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "1")

    # the unmutated copies, placed where the mutants go, must validate: else a mutant's
    # error could be about where it is (a mesh path that no longer resolves)
    for p, data in sources:
        copy = work / "mutants" / ("original_" + p.name)
        copy.write_bytes(data)
        code, out, err, _ = run([str(binary), "--validate", str(copy)], work, args.timeout, env)
        if code != 0:
            print("fuzz: the unmutated copy of %s does not validate in %s (exit %s):\n%s%s"
                  % (p, work, code, out, err), file=sys.stderr)
            return 1
        copy.unlink()

    print("fuzz: seed %d, %d scenes, %s, binary %s" % (
        args.seed, len(sources),
        ("%d cases" % args.cases if args.cases is not None else "")
        + (" " if args.cases is not None and args.budget is not None else "")
        + ("budget %g s" % args.budget if args.budget is not None else ""), binary))
    sys.stdout.flush()

    start = time.monotonic()
    histogram = collections.Counter()
    failures = []
    cases = 0
    valid_seen = collections.Counter()
    short_runs = 0
    budget_hit = False
    index = args.first
    while True:
        if args.cases is not None and cases >= args.cases:
            break
        if args.budget is not None and time.monotonic() - start >= args.budget:
            budget_hit = args.cases is not None
            break
        s, data, what = make_case(args.seed, index, sources)
        source = sources[s][0]
        mutant = work / "mutants" / ("case%05d_%s" % (index, source.name))
        mutant.write_bytes(data)
        checks = [("validate", [str(binary), "--validate", str(mutant)], args.timeout)]
        code, out, err, seconds = run(checks[0][1], work, args.timeout, env)
        results = [("validate", checks[0][1], code, out, err, seconds)]
        histogram["validate %s" % code] += 1
        kind = short_run_kind(data)  # the mutant's: a mutation may have made it accurate
        if code == 0 and kind and args.short_run_every > 0:
            valid_seen[kind] += 1
            if sum(valid_seen.values()) % args.short_run_every == 1 or args.short_run_every == 1:
                output = work / "runs" / mutant.stem
                command = [str(binary), str(mutant), "--output", str(output),
                           "--set", "Time/End time=%g" % args.end_time]
                if kind == "suture":
                    command += ["--set", "Time/Step size=%g" % args.end_time]
                rcode, rout, rerr, rseconds = run(command, work, args.run_timeout, env)
                results.append(("run", command, rcode, rout, rerr, rseconds))
                histogram["run %s" % rcode] += 1
                short_runs += 1
                shutil.rmtree(output, ignore_errors=True)
        case_failed = False
        for kind_, command, c, o, e, sec in results:
            reason = verdict(kind_, c, o, e, mutant, data)
            if reason is None and (work / "fuzz_pwned").exists():
                reason = "a value ran as a shell command (it created fuzz_pwned)"
            if args.verbose:
                print("case %d %s %s: exit %s %.1f s: %s%s" % (index, source.name, kind_, c, sec, what,
                                                              "" if reason is None else "  FAIL: " + reason))
            if reason is None:
                continue
            case_failed = True
            failures.append((index, source, what, kind_, command, c, reason))
            print("\nFAIL case %d (%s, %s): %s" % (index, source.relative_to(root) if root in source.parents
                                                   else source, kind_, reason))
            print("  mutation: %s" % what)
            print("  command:  %s" % " ".join(command))
            print("  exit:     %s after %.1f s" % (c, sec))
            for label, text in (("stdout", o), ("stderr", e)):
                shown = text.splitlines()[:8]
                for l in shown:
                    print("  %s| %s" % (label, l[:300]))
                if len(text.splitlines()) > len(shown):
                    print("  %s| ... (%d lines)" % (label, len(text.splitlines())))
            sys.stdout.flush()
        if case_failed:
            shutil.copy(mutant, work / "failures" / mutant.name)
            with open(work / "failures" / (mutant.name + ".txt"), "w") as f:
                f.write("seed %d case %d source %s\nmutation: %s\n" % (args.seed, index, source, what))
                for kind_, command, c, o, e, sec in results:
                    f.write("\n$ %s\nexit %s after %.1f s\n--- stdout\n%s--- stderr\n%s" % (
                        " ".join(command), c, sec, o[-20000:], e[-20000:]))
        if not (args.keep or case_failed):
            mutant.unlink()
        cases += 1
        index += 1
        if build_stamp(binary) != stamp:
            print("fuzz: %s changed during the run (rebuilt?): the results are void" % binary, file=sys.stderr)
            return 1

    elapsed = time.monotonic() - start
    print("\nfuzz: %d cases (%d to %d), seed %d, %d short runs, %.0f s" % (
        cases, args.first, index - 1, args.seed, short_runs, elapsed))
    for key in sorted(histogram, key=lambda k: (k.split()[0] != "validate", k)):
        print("  %-16s %d" % (key, histogram[key]))
    if budget_hit:
        print("fuzz: the budget of %g s ran out before case %d of %d" % (args.budget, cases, args.cases))
    if failures:
        print("fuzz: %d FAILURES (mutants and outputs in %s):" % (len(failures), work / "failures"))
        for index, source, what, kind_, command, c, reason in failures:
            print("  case %d %s %s: %s  [%s]" % (index, source.name, kind_, reason, what))
        extra = ""
        if args.sources:
            extra += " --sources " + " ".join(str(p) for p, _ in sources)
        if args.short_run_every != 1:
            extra += " --short-run-every %d" % args.short_run_every
        if args.end_time != 0.01:
            extra += " --end-time %g" % args.end_time
        print("reproduce one: %s %s --suturesim %s --seed %d%s --first N --cases 1 --work DIR --verbose" % (
            sys.executable, Path(__file__).resolve(), binary, args.seed, extra))
        return 1
    print("fuzz: no failure")
    return 0


if __name__ == "__main__":
    sys.exit(main())
