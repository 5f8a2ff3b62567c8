#!/usr/bin/env python3
"""The lines a change adds follow .clang-format: clang-format's own `git clang-format --diff`
over what changed since BASE (by default the commit that brought the format rule in, so the
code written before it is not reformatted wholesale, and everything written after it is held
to it).

    tools/check_format.py [--base REV] [ROOT]   what clang-format would change, exit 1 if any
    tools/check_format.py --self-test           plants a misformatted change in a scratch repo
"""
import os
import subprocess
import sys
import tempfile

EXTENSIONS = "cpp,hpp,h,cc"


def git(root, *args, check=True):
    return subprocess.run(["git", "-C", root, *args], check=check, capture_output=True, text=True)


def rule_commit(root):
    out = git(root, "log", "--diff-filter=A", "--format=%H", "-1", "--", ".clang-format", check=False)
    return out.stdout.strip()


def wanted_changes(root, base):
    """clang-format's diff for the lines changed since base ('' when they follow the rule)."""
    out = git(root, "clang-format", "--diff", "--extensions", EXTENSIONS, base, check=False)
    text = out.stdout + out.stderr
    return text if "diff --git" in text or out.returncode not in (0, 1) else ""


def check(root, base):
    base = base or rule_commit(root)
    if not base:
        # A tarball or a shallow clone: no history to tell new lines from old (the self-test
        # still exercises the check).
        print(f"check_format: no commit adding .clang-format in {root}'s history: nothing compared")
        return 0
    changes = wanted_changes(root, base)
    if changes:
        print(changes)
        print(f"check_format: lines changed since {base[:12]} do not follow .clang-format "
              f"(fix: git add the change, then git clang-format {base[:12]})", file=sys.stderr)
        return 1
    print(f"check_format: lines changed since {base[:12]} follow .clang-format")
    return 0


def self_test():
    with tempfile.TemporaryDirectory() as root:
        git(root, "init", "-q")
        git(root, "config", "user.email", "check@arphys")
        git(root, "config", "user.name", "check")
        with open(os.path.join(root, ".clang-format"), "w") as f:
            f.write("BasedOnStyle: Google\nColumnLimit: 120\n")
        source = os.path.join(root, "a.cpp")
        with open(source, "w") as f:
            f.write("int   old_style( int x ){return x;}\n")  # before the rule: not checked
        git(root, "add", ".")
        git(root, "commit", "-q", "-m", "rule")
        with open(source, "a") as f:
            f.write("int   added( int x ){return x;}\n")
        if check(root, "") != 1:
            print("self-test: a misformatted added line passed", file=sys.stderr)
            return 1
        if check(root, "HEAD") != 1:
            print("self-test: --base HEAD missed the uncommitted change", file=sys.stderr)
            return 1
        with open(source, "w") as f:
            f.write("int   old_style( int x ){return x;}\nint added(int x) { return x; }\n")
        if check(root, "") != 0:
            print("self-test: a well-formatted added line failed", file=sys.stderr)
            return 1
    print("self-test: a misformatted change is found, a formatted one passes, old code is left alone")
    return 0


def main(argv):
    if "--self-test" in argv:
        return self_test()
    base = ""
    if "--base" in argv:
        i = argv.index("--base")
        base = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    root = argv[0] if argv else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    return check(root, base)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
