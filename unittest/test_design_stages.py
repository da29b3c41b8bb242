"""doc/design.md's stage tables against the code: every fix style the plugins register (src/
sphcut_plugin.cpp, KOKKOS/sphcut_kokkos_plugin.cpp) must appear in the tables headed
`| stage | style | ...` at exactly the callbacks its setmask() sets (FixConst masks, its base
class's included where it calls or inherits it; a mask set under a condition counts), and a fix
must not define a callback (Class::post_force ...) that its mask never sets.  Fails naming the
style, the callbacks the table lists and those the code sets.
Usage: python3 test_design_stages.py [SOURCE_DIR]   (default: the folder above this file)"""
import os
import re
import sys

# the FixConst masks of a step (LAMMPS fix.h) and the callbacks they enable
CALLBACKS = ("initial_integrate", "post_integrate", "pre_exchange", "pre_neighbor", "post_neighbor",
             "pre_force", "pre_reverse", "post_force", "final_integrate", "end_of_step")
# (post_run is left out: LAMMPS calls it for every fix, whatever the mask)

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
errors = []


def read(rel):
    with open(os.path.join(root, rel)) as f:
        return f.read()


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def documented():
    """{style name: set of callbacks} from every table of design.md headed | stage | style |"""
    doc = {}
    in_table, stage = False, None
    for line in read("doc/design.md").splitlines():
        if not line.startswith("|"):
            in_table = False
            continue
        c = cells(line)
        if len(c) >= 2 and c[0] == "stage" and c[1] == "style":
            in_table, stage = True, None
            continue
        if not in_table or (c[0] and set(c[0]) <= set("-: ")):
            continue
        if c[0]:
            # the callbacks named in the stage cell (a row may name several: `pre_exchange`, `post_neighbor`)
            stage = [s for s in re.findall(r"`([a-z_]+)`", c[0]) if s in CALLBACKS]
        m = re.match(r"(fix|pair|compute)\s+([a-z0-9/_-]+)", c[1])
        if m and stage:
            doc.setdefault(f"{m.group(1)} {m.group(2)}", set()).update(stage)
        elif m:
            doc.setdefault(f"{m.group(1)} {m.group(2)}", set())
    return doc


def registered():
    """[(style name, class)] of the fix styles both plugins register"""
    out = []
    for rel, suffixes in (("src/sphcut_plugin.cpp", ("",)), ("KOKKOS/sphcut_kokkos_plugin.cpp", ("/kk",))):
        if not os.path.exists(os.path.join(root, rel)):
            continue
        text = read(rel)
        for m in re.finditer(r'"fix",\s*"([^"]+)",.*?fix_creator<(\w+)', text, re.S):
            for s in suffixes:
                out.append((f"fix {m.group(1)}{s}", m.group(2)))
    return out


SOURCES = {rel: read(rel) for d in ("src", "KOKKOS") if os.path.isdir(os.path.join(root, d))
           for rel in (os.path.join(d, f) for f in sorted(os.listdir(os.path.join(root, d))))
           if rel.endswith((".cpp", ".h"))}


def bases(cls):
    """the sphcut base classes of cls (LAMMPS' Fix and the helper bases left out)"""
    for text in SOURCES.values():
        m = re.search(r"class\s+" + cls + r"\s*:\s*([^{]+)\{", text)
        if m:
            return [b for b in re.findall(r"public\s+(\w+)", m.group(1)) if b.startswith("Fix") and b != "Fix"]
    return []


def body_of(cls, method):
    """the body of cls::method (templated classes too), or None"""
    pat = re.compile(r"\b" + cls + r"(?:<\w+>)?::" + method + r"\s*\([^)]*\)\s*(?:const\s*)?\{")
    for text in SOURCES.values():
        m = pat.search(text)
        if m:
            depth, k = 1, m.end()
            while depth and k < len(text):
                depth += {"{": 1, "}": -1}.get(text[k], 0)
                k += 1
            return text[m.end():k - 1]
    return None


def mask(cls):
    """the callbacks cls's setmask() can set (its own, or its base's where it calls or inherits it)"""
    body = body_of(cls, "setmask")
    if body is None:
        return set().union(*(mask(b) for b in bases(cls))) if bases(cls) else set()
    out = {w.lower() for w in re.findall(r"\b([A-Z_]+)\b", body) if w.lower() in CALLBACKS}
    for b in re.findall(r"(\w+)::setmask\s*\(", body):
        out |= mask(b)
    return out


def defines(cls):
    """the step callbacks cls or its sphcut bases define"""
    own = {cb for cb in CALLBACKS if body_of(cls, cb) is not None}
    return own.union(*(defines(b) for b in bases(cls)))


doc = documented()
fixes = registered()
if not fixes:
    errors.append("no fix styles found in src/sphcut_plugin.cpp: the test cannot check anything")
for style, cls in fixes:
    code = mask(cls)
    if not code:
        errors.append(f"{style} ({cls}): no setmask() found in src/ or KOKKOS/")
        continue
    if style not in doc:
        errors.append(f"{style} ({cls}) is not in a '| stage | style |' table of doc/design.md; "
                      f"its setmask() sets: {' '.join(sorted(code))}")
        continue
    if doc[style] != code:
        missing, extra = code - doc[style], doc[style] - code
        errors.append(f"{style} ({cls}): doc/design.md lists {' '.join(sorted(doc[style])) or 'nothing'}, "
                      f"setmask() sets {' '.join(sorted(code))}"
                      + (f"; not in the table: {' '.join(sorted(missing))}" if missing else "")
                      + (f"; in the table but not set: {' '.join(sorted(extra))}" if extra else ""))
    dead = defines(cls) - code
    if dead:
        errors.append(f"{style} ({cls}) defines {' '.join(sorted(dead))} but its setmask() never sets it: "
                      "LAMMPS never calls it")
for style in sorted(set(doc) - {s for s, _ in fixes}):
    if style.startswith("fix "):
        errors.append(f"doc/design.md lists {style}, which neither plugin registers")

if errors:
    print("doc/design.md's stage tables do not match the styles' callbacks:")
    for e in errors:
        print("  " + e)
    sys.exit(1)
print(f"doc/design.md matches setmask() of {len(fixes)} fix styles: "
      + "; ".join(f"{s}: {' '.join(sorted(doc[s]))}" for s, _ in fixes))
