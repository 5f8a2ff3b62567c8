#!/usr/bin/env python3
"""Each .cpp compiles on its own. The unity builds put eight files of a target into one
translation unit, so a file can lean on what the file before it in its batch includes and
still build, until the batches move. This compiles every source alone, syntax only, with
its target's flags as a build's compile_commands.json gives them.

    tools/check_includes.py [--since REV] [-j N] BUILD_DIR   exit 1 if a file does not compile alone
    tools/check_includes.py --self-test                      plants a file that leans on its batch
"""
import argparse
import concurrent.futures
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile

UNITY_INCLUDE = re.compile(r'^#include\s+"([^"]+\.(?:cpp|cc|c))"', re.MULTILINE)


def sources_of(entry):
    """(source, command words) for each file one compile_commands entry compiles."""
    words = shlex.split(entry["command"]) if "command" in entry else list(entry["arguments"])
    path = entry["file"]
    if "/Unity/unity_" in path:
        with open(path) as f:
            files = UNITY_INCLUDE.findall(f.read())
    else:
        files = [path]
    return [(source, words) for source in files]


def syntax_only(words, source):
    """The entry's command compiling source alone, checking syntax and types only."""
    out, skip = [], False
    for word in words:
        if skip:
            skip = False
        elif word in ("-o", "-c"):
            skip = True
        else:
            out.append(word)
    return out + ["-fsyntax-only", source]


def changed_since(rev, root):
    out = subprocess.run(["git", "-C", root, "diff", "--name-only", rev, "--"], capture_output=True, text=True,
                         check=True)
    return {os.path.realpath(os.path.join(root, name)) for name in out.stdout.split()}


def check(build_dir, since="", jobs=os.cpu_count() or 2):
    with open(os.path.join(build_dir, "compile_commands.json")) as f:
        entries = json.load(f)
    work = {}
    for entry in entries:
        for source, words in sources_of(entry):
            work.setdefault(os.path.realpath(source), (words, entry["directory"]))
    if since:
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        wanted = changed_since(since, root)
        work = {source: job for source, job in work.items() if source in wanted}

    def run(item):
        source, (words, directory) = item
        done = subprocess.run(syntax_only(words, source), cwd=directory, capture_output=True, text=True)
        return source, done.returncode, done.stderr

    failed = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        for source, code, stderr in pool.map(run, sorted(work.items())):
            if code != 0:
                failed += 1
                print(f"{source}: does not compile alone", file=sys.stderr)
                print("\n".join(stderr.splitlines()[:12]), file=sys.stderr)
    print(f"check_includes: {len(work) - failed} of {len(work)} sources compile alone")
    return 1 if failed else 0


def self_test():
    with tempfile.TemporaryDirectory() as build:
        with open(os.path.join(build, "a.cpp"), "w") as f:
            f.write("#include <vector>\nstd::vector<int> a;\n")
        with open(os.path.join(build, "b.cpp"), "w") as f:
            f.write("std::vector<int> b;  // leans on a.cpp's include\n")
        os.makedirs(os.path.join(build, "Unity"))
        unity = os.path.join(build, "Unity", "unity_0_cxx.cxx")
        with open(unity, "w") as f:
            f.write(f'#include "{build}/a.cpp"\n\n#include "{build}/b.cpp"\n')
        compiler = os.environ.get("CXX", "c++")
        entry = {"directory": build, "file": unity, "command": f"{compiler} -std=c++17 -o u.o -c {unity}"}
        with open(os.path.join(build, "compile_commands.json"), "w") as f:
            json.dump([entry], f)
        if subprocess.run(shlex.split(entry["command"]), cwd=build).returncode != 0:
            print("self-test: the planted batch does not build at all", file=sys.stderr)
            return 1
        if check(build) != 1:
            print("self-test: b.cpp, which leans on its batch, passed", file=sys.stderr)
            return 1
        with open(os.path.join(build, "b.cpp"), "w") as f:
            f.write("#include <vector>\nstd::vector<int> b;\n")
        if check(build) != 0:
            print("self-test: sources that include what they use failed", file=sys.stderr)
            return 1
    print("self-test: a file leaning on its batch is found, self-contained ones pass")
    return 0


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("build_dir", nargs="?", help="a configured build tree (its compile_commands.json)")
    parser.add_argument("--since", default="", metavar="REV", help="only the sources changed since REV")
    parser.add_argument("-j", type=int, default=os.cpu_count() or 2, dest="jobs", help="compilers at a time")
    parser.add_argument("--self-test", action="store_true", help="plant a file leaning on its batch")
    args = parser.parse_args(argv)
    if args.self_test:
        return self_test()
    if not args.build_dir:
        parser.error("a build directory is needed")
    return check(args.build_dir, args.since, args.jobs)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
