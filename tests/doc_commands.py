#!/usr/bin/env python3
"""Run every shell command that README.md and the pages under doc/ show, so that an
example cannot rot unnoticed (issue 38: a README command failed for months).

    python3 tests/doc_commands.py SOURCE_DIR BUILD_DIR [--python P] [--steps N] [--timeout S]

A command is a line of a code block (indented by four spaces, or fenced as ``` or ```sh)
whose first word is one of COMMAND_WORDS, with its continuation lines ("\\"); "a && b" is
two commands. Each runs in one scratch folder where build/ is BUILD_DIR and the source
tree's folders are linked, in the order the pages show them (a command may use what an
earlier one wrote, as a reader's would), with a time limit of --timeout seconds:
- every scene file the command names (parameters/NAME.prm) is replaced by a file of the
  same name that includes it and cuts Time stepping/Number of steps to --steps, so that a
  scene runs as the page says in seconds;
- mpirun may run as root (the CI does), and python3 is --python (the module's);
- the commands listed in NOT_RUN are not run, each for the reason it gives, which this
  test prints: those that take more than about a minute, or install, or are the test suite.

Fails (exit 1) if a command fails or runs out of time, or if an entry of NOT_RUN is shown by
no page any more (the list follows the pages).
"""

import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

# The words a command of the pages starts with (after VAR=value assignments).
COMMAND_WORDS = re.compile(r"^(build/|build-sanitize/|benchmarks/|python/|doc/|~/venvs/|"
                           r"sh$|python3$|mpirun$|cmake$|ctest$|mkdir$|xvfb-run$)")

# The marker of a command not run here: the command as its page writes it (without its
# comment), and why.
NOT_RUN = {
    "sh .ci/setup": "installs Debian packages and builds: this suite runs on its build",
    "ctest --test-dir build --output-on-failure -j2": "the test suite itself",
    "ctest --test-dir build-sanitize -R fuzz": "the sanitizer build's suite (sh .ci/sanitize)",
    "sh .ci/sanitize": "builds everything again with the sanitizers: about an hour",
    "build-sanitize/fuzz/fuzz_gmsh -seed=0 -max_total_time=300 -dict=fuzz/dictionaries/gmsh.dict "
    "-timeout=10 -rss_limit_mb=2048 NEW_CORPUS/ fuzz/corpus/gmsh fuzz/regressions/gmsh":
        "the sanitizer build's fuzzer, 5 minutes (sh .ci/sanitize runs its regressions)",
    "sh benchmarks/report_tables.sh": "about 5 minutes",
    "sh benchmarks/solver.sh": "a few minutes",
    "sh benchmarks/targets.sh": "every SIMD target's kernels and study goals: about 30 minutes",
    "sh benchmarks/kernel_targets.sh": "every kernel on every SIMD target: minutes",
    "sh benchmarks/distributed.sh": "about 6 minutes",
    "sh benchmarks/backends.sh": "about 35 minutes",
    "sh benchmarks/study.sh": "about 25 minutes",
    "sh benchmarks/calibration.sh": "ten scenes at many thresholds: about an hour",
    "sh benchmarks/updates.sh": "rank-k updates against CHOLMOD on four matrices: minutes",
    "sh benchmarks/surgery.sh": "the four scenes with changes, each change each way: minutes",
    "sh doc/pictures/make.sh": "about a minute, and it rewrites the pictures in the source tree",
    "mpirun -np 2 build/warpchol parameters/torus_pull_1m.prm": "1.2M tetrahedra: minutes, and gigabytes",
    "cmake --install build --prefix /tmp/warpchol": "install/step-8-partial runs it (tests/install_example.sh)",
    "cmake -S examples/step-8-partial -B /tmp/step-8-partial -DCMAKE_BUILD_TYPE=Release "
    "-DCMAKE_PREFIX_PATH=/tmp/warpchol": "install/step-8-partial builds the example (tests/install_example.sh)",
    "cmake --build /tmp/step-8-partial": "install/step-8-partial builds the example (tests/install_example.sh)",
    "python3 -m venv --system-site-packages ~/venvs/warpchol": "python/install_venv makes a venv (tests it outside the trees)",
    "~/venvs/warpchol/bin/python -m pip install --no-build-isolation --no-index ./python":
        "python/install_venv installs the package with pip into a fresh venv",
    "~/venvs/warpchol/bin/python -c \"import warpchol; print(warpchol.SparseCholesky.__doc__)\"":
        "python/install_venv imports the package from its venv",
    "python3 -m pip install --no-build-isolation --no-index --break-system-packages ./python":
        "installs into the system's Python; python/install_venv tests the same install in a venv",
}


def code_lines(text):
    """The lines of the code blocks of a Markdown page: fenced (``` or ```sh) or indented by four."""
    lines, fence, previous_blank, in_indented = [], None, True, False
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("```"):
            fence = None if fence is not None else stripped[3:].strip()
            in_indented = False
            continue
        if fence is not None:
            if fence in ("", "sh", "shell", "bash", "console"):
                lines.append(line)
            continue
        # A block starts after a blank line, with no list item's "-" or "*" (a list's
        # continuation); its later lines may start with anything (an option, say).
        if line.startswith("    ") and (in_indented or (previous_blank and not line.lstrip().startswith(("-", "*", "|")))):
            in_indented = True
            lines.append(line[4:])
        elif stripped:
            in_indented = False
        previous_blank = not stripped
    return lines


def commands_of(text):
    """The page's commands in order, each "a && b" split, comments and continuations resolved."""
    commands, pending = [], ""
    for line in code_lines(text):
        line = pending + line.strip()
        if line.endswith("\\"):
            pending = line[:-1] + " "
            continue
        pending = ""
        line = re.sub(r"\s+#.*$", "", line)
        for part in line.split("&&"):
            part = " ".join(part.split())
            words = part.split()
            while words and re.match(r"^[A-Z_]+=", words[0]):
                words = words[1:]
            if words and COMMAND_WORDS.match(words[0]):
                commands.append(part)
    return commands


def shortened(command, source, scratch, steps):
    """@p command with each parameters/NAME.prm replaced by NAME.prm cut to @p steps steps."""
    def replace(match):
        name = match.group(1)
        folder = os.path.join(scratch, "short")
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, name + ".prm"), "w") as prm:
            prm.write("include " + os.path.join(source, "parameters", name + ".prm") + "\n"
                      "subsection Time stepping\n  set Number of steps = %d\nend\n" % steps)
        return "short/" + name + ".prm"
    return re.sub(r"(?<![\w/])parameters/([\w.-]+)\.prm\b", replace, command)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source")
    parser.add_argument("build")
    parser.add_argument("--python", default=sys.executable, help="the python3 the commands run")
    parser.add_argument("--steps", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=90)
    options = parser.parse_args()
    source, build = os.path.abspath(options.source), os.path.abspath(options.build)

    pages = ["README.md"] + sorted("doc/" + name for name in os.listdir(os.path.join(source, "doc"))
                                   if name.endswith(".md"))
    shown, failures = [], 0
    for page in pages:
        with open(os.path.join(source, page)) as text:
            shown += [(page, command) for command in commands_of(text.read())]

    scratch = tempfile.mkdtemp(prefix="doc_commands.")
    os.symlink(build, os.path.join(scratch, "build"))
    for name in os.listdir(source):
        if name not in ("build", "output") and not name.startswith(".git"):
            os.symlink(os.path.join(source, name), os.path.join(scratch, name))
    tools = os.path.join(scratch, ".bin")
    os.mkdir(tools)
    os.symlink(options.python, os.path.join(tools, "python3"))
    environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                       OMPI_MCA_rmaps_base_oversubscribe="1", PATH=tools + os.pathsep + os.environ["PATH"])

    done = set()
    for page, command in shown:
        if command in done:
            continue
        done.add(command)
        if command in NOT_RUN:
            print("%s: not run: %s: %s" % (page, command, NOT_RUN[command]))
            continue
        run = shortened(command, source, scratch, options.steps)
        start = time.time()
        try:
            result = subprocess.run(run, shell=True, cwd=scratch, env=environment, timeout=options.timeout,
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            status = "exit %d" % result.returncode
            failed = result.returncode != 0
        except subprocess.TimeoutExpired as expired:
            result, status, failed = expired, "out of time after %g s" % options.timeout, True
        print("%s: %s: %s, %.1f s" % (page, command, status, time.time() - start))
        if failed:
            failures += 1
            output = result.stdout if isinstance(result.stdout, str) else (result.stdout or b"").decode(errors="replace")
            print("  ran: " + run)
            print("  " + "\n  ".join(output.strip().splitlines()[-15:]))

    stale = sorted(set(NOT_RUN) - {command for _, command in shown})
    for command in stale:
        print("NOT_RUN names a command no page shows any more: " + command)
    shutil.rmtree(scratch, ignore_errors=True)
    print("%d commands shown, %d run, %d not run, %d failed" %
          (len(done), len(done) - len(set(NOT_RUN) & done), len(set(NOT_RUN) & done), failures))
    return 1 if failures or stale else 0


if __name__ == "__main__":
    sys.exit(main())
