#!/usr/bin/env python3
"""The house's layering, checked: which project folders a folder's sources may include.

    tools/check_layering.py [ROOT]     every violation as FILE:LINE, exit 1 if any
    tools/check_layering.py --self-test

Libraries never include what sits above them: the engine (simulator/geometry, collision,
dynamics) knows no scene file, process or tool; tracker and renderer use only the shared
geometry of the simulator; the unit tests of the libraries use no tools. System and
package headers (<...>) are not checked, nor are folders without a rule."""
import os
import re
import sys
import tempfile

# folder -> the project folders its files may include (prefixes of the include path)
ENGINE = ["simulator/geometry/"]
RULES = [
    ("simulator/geometry/", ENGINE),
    ("simulator/collision/", ENGINE + ["simulator/collision/"]),
    ("simulator/dynamics/", ENGINE + ["simulator/collision/", "simulator/dynamics/"]),
    ("configs/", ["configs/"] + ENGINE),
    ("lcmtypes/", ["lcmtypes/", "arphys/"] + ENGINE),
    ("tracker/", ["tracker/", "configs/", "lcmtypes/", "arphys/"] + ENGINE),
    ("renderer/", ["renderer/", "configs/", "lcmtypes/", "arphys/"] + ENGINE),
]
# folder -> project folders its files must not include
FORBIDDEN = [(f"tests/{lib}/", ["tools/"]) for lib in ("simulator", "tracker", "renderer", "configs", "lcmtypes")]

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
SOURCES = (".hpp", ".cpp", ".h", ".cc")


def problem(rel, header):
    for folder, allowed in RULES:
        if rel.startswith(folder) and not any(header.startswith(a) for a in allowed) and "/" in header:
            return f"{folder} may include only {', '.join(allowed)}"
    for folder, denied in FORBIDDEN:
        if rel.startswith(folder) and any(header.startswith(d) for d in denied):
            return f"{folder} must not include {', '.join(denied)}"
    return None


def violations(root):
    found = []
    for top in [r[0] for r in RULES] + [f[0] for f in FORBIDDEN]:
        base = os.path.join(root, top)
        for directory, _, names in os.walk(base):
            for name in sorted(n for n in names if n.endswith(SOURCES)):
                path = os.path.join(directory, name)
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                with open(path, encoding="utf-8", errors="replace") as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        why = m and problem(rel, m.group(1))
                        if why:
                            found.append(f"{rel}:{number}: includes \"{m.group(1)}\" ({why})")
    return sorted(set(found))


def self_test():
    with tempfile.TemporaryDirectory() as root:
        for rel, text in [("simulator/dynamics/a.hpp", '#include "configs/loader/scene_config.hpp"\n'),
                          ("simulator/dynamics/b.hpp", '#include "simulator/collision/shape.hpp"\n#include <vector>\n'),
                          ("tracker/c.cpp", '#include "simulator/dynamics/world.hpp"\n'),
                          ("tests/simulator/d_test.cpp", '#include "tools/ccd_bench/fcl_reference.hpp"\n')]:
            os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
            with open(os.path.join(root, rel), "w") as f:
                f.write(text)
        got = [v.split(":")[0] for v in violations(root)]
        want = ["simulator/dynamics/a.hpp", "tests/simulator/d_test.cpp", "tracker/c.cpp"]
        if got != want:
            print(f"check_layering self-test: found {got}, expected {want}", file=sys.stderr)
            return 1
    print("check_layering self-test: the planted violations are found, the allowed include is not")
    return 0


def main(argv):
    if argv[1:] in (["-h"], ["--help"]):
        print(__doc__)
        return 0
    if argv[1:] == ["--self-test"]:
        return self_test()
    root = argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    found = violations(root)
    for v in found:
        print(v, file=sys.stderr)
    print(f"check_layering: {len(found)} forbidden includes", file=sys.stderr if found else sys.stdout)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
