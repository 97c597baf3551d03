"""Shared pieces of the benchmarks' compare.py scripts (/usr/bin/python3).

Each benchmark folder holds its scene, reference.json (the reference values with their
source and the tolerances), compare.py and README.md. The compare scripts read a run's
summary.json and parameters.prm, optionally make the runs first (--run BINARY), print a
Markdown table and exit with 1 when a value is outside its stated tolerance.
"""
import argparse
import json
import math
import shlex
import subprocess
import sys
from pathlib import Path


def folder_of(script):
    return Path(script).resolve().parent


def reference(script):
    """reference.json next to the calling compare.py."""
    return json.load(open(folder_of(script) / "reference.json"))


def arguments(doc, runs_help="run folders (made by --run, or by the commands in README.md)"):
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output", help="folder that holds (or receives, with --run) the runs")
    parser.add_argument("--run", metavar="SUTURESIM", help="make the runs first with this binary")
    parser.add_argument("--no-figure", action="store_true", help="skip the PNG/PDF figure")
    parser.epilog = runs_help
    return parser


def run(binary, scene, output, settings=(), launcher=(), expected_exit=0):
    """`binary scene --output output --set ...`; exits on any other exit status than
    expected_exit (a scene may be made to end in a failed step), the log kept."""
    output = Path(output)
    output.parent.mkdir(parents=True, exist_ok=True)
    command = [*launcher, str(binary), str(scene), "--output", str(output)]
    for s in settings:
        command += ["--set", s]
    print("$ " + " ".join(shlex.quote(c) for c in command), flush=True)
    with open(str(output) + ".log", "w") as log:
        status = subprocess.call(command, stdout=log, stderr=subprocess.STDOUT)
    if status != expected_exit:
        sys.exit(f"the run ended with exit {status}, not {expected_exit}; see {output}.log")
    return output


def summary(run_folder):
    return json.load(open(Path(run_folder) / "summary.json"))


def parameters(run_folder):
    """parameters.prm of a run as {"Sub/Sub/Key": value string}."""
    values, path = {}, []
    for line in open(Path(run_folder) / "parameters.prm"):
        line = line.split("#", 1)[0].strip()
        if line.startswith("subsection "):
            path.append(line[len("subsection "):].strip())
        elif line == "end":
            path.pop()
        elif line.startswith("set "):
            key, value = line[4:].split("=", 1)
            values["/".join(path + [key.strip()])] = value.strip()
    return values


def table(header, rows):
    """A Markdown table; floats in the rows are printed as given (format them first)."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    print("\n".join(lines))


def rate(e_coarse, e_fine, ratio=2):
    """Observed order log(e_coarse / e_fine) / log(ratio); nan when undefined."""
    if e_coarse > 0 and e_fine > 0:
        return math.log(e_coarse / e_fine) / math.log(ratio)
    return float("nan")


def sent_shape_factor(x):
    """F(a/W) of the long single-edge-cracked strip in tension (Tada, Paris & Irwin, The
    Stress Analysis of Cracks Handbook, 3rd ed., 2000; better than 0.5 % for a/W <= 0.6)."""
    return 1.12 - 0.231 * x + 10.55 * x ** 2 - 21.72 * x ** 3 + 30.39 * x ** 4


def at1_effective_toughness(gc, ell, h):
    """AT1's toughness on cells of size h: G_c (1 + 3h/(8l)) (Bourdin, Francfort & Marigo,
    J Elasticity 91:5, 2008, section 8.1.1)."""
    return gc * (1 + 3 * h / (8 * ell))


def plane_strain_modulus(E, nu):
    """E' = E / (1 - nu^2)."""
    return E / (1 - nu * nu)


def sent_critical_traction(E, nu, gc, ell, h, a, W):
    """LEFM's critical traction of single-edge-notched tension in plane strain with AT1's
    discretised toughness: sqrt(E' G_eff / (pi a)) / F(a/W)."""
    return math.sqrt(plane_strain_modulus(E, nu) * at1_effective_toughness(gc, ell, h) / (math.pi * a)) \
        / sent_shape_factor(a / W)


def sent_mouth_opening(E, nu, sigma, a, W):
    """The crack mouth's opening of the long single-edge-cracked strip in plane strain under
    the traction sigma: 4 sigma a V1(a/W) / E', V1(x) = (1.46 + 3.42 (1 - cos(pi x/2))) /
    cos^2(pi x/2) (Tada, Paris & Irwin, The Stress Analysis of Cracks Handbook, 3rd ed.,
    2000, single edge cracked strip in tension; 1 % for any a/W)."""
    c = math.cos(math.pi * a / (2 * W))
    return 4 * sigma * a * (1.46 + 3.42 * (1 - c)) / c ** 2 / plane_strain_modulus(E, nu)


def save_figure(fig, stem):
    """stem.png and stem.pdf."""
    for suffix in (".png", ".pdf"):
        fig.savefig(str(stem) + suffix, dpi=150, bbox_inches="tight")
    print(f"wrote {stem}.png, {stem}.pdf")


def pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def verdict(failures):
    """Prints the failures and exits 1, or prints PASS."""
    if failures:
        for f in failures:
            print("FAIL: " + f)
        sys.exit(1)
    print("PASS")
