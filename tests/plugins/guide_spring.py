#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The plugin guide works as written (docs/plugin-guide.md): its `spring` model, made the way
the guide says -- the template plugins/template/null_model.cpp renamed, its class body replaced
by the guide's code blocks of sections 2 and 3 (the forwarding overrides deleted) -- compiles
with warnings as errors; the C++ test of section 5 compiles against the SDK and Catch2; and the
Lua blocks of sections 4 and 5 run with the library built and print what the guide says.

usage: guide_spring.py TALUS SOURCE_DIR CXX WORK_DIR [INCLUDE_DIRS]
INCLUDE_DIRS: ':'-separated directories of the C++ test's other headers (Eigen, Catch2).
"""
import os
import shutil
import subprocess
import sys

talus, src, cxx, work = sys.argv[1:5]
includes = [d for d in (sys.argv[5].split(":") if len(sys.argv) > 5 else []) if d]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("check failed:", what)


def blocks(markdown):
    """(section heading, language, code) of every fenced block, in order."""
    out, section, lang, code = [], "", None, []
    for line in markdown.splitlines():
        if lang is None:
            if line.startswith("## "):
                section = line[3:].strip()
            elif line.startswith("```"):
                lang, code = line[3:].strip(), []
        elif line.startswith("```"):
            out.append((section, lang, "\n".join(code) + "\n"))
            lang = None
        else:
            code.append(line)
    return out


guide = open(os.path.join(src, "docs", "plugin-guide.md")).read()
found = blocks(guide)
cpp_model = [c for s, l, c in found if l == "cpp" and (s.startswith("2.") or s.startswith("3."))]
cpp_test = [c for s, l, c in found if l == "cpp" and s.startswith("5.")]
lua = [c for s, l, c in found if l == "lua" and (s.startswith("4.") or s.startswith("5."))]
check(len(cpp_model) == 2 and len(cpp_test) == 1 and len(lua) == 3,
      f"the guide's blocks: {len(cpp_model)} model, {len(cpp_test)} test, {len(lua)} Lua")

# The template, renamed as section 1 says, its class body replaced by the guide's code.
template = open(os.path.join(src, "plugins", "template", "null_model.cpp")).read()
head, rest = template.split("class Null final", 1)
tail = rest[rest.index("ContactModel* createPrototype"):]
spring = (head + "class Spring final : public ModelBase<Spring> {\n"
          "    using Base = ModelBase<Spring>;\n\npublic:\n"
          '    static constexpr const char* kName = "spring";\n\n'
          + "\n".join(cpp_model) + "};\n\n" + tail.replace("Null", "Spring"))

shutil.rmtree(work, ignore_errors=True)
os.makedirs(os.path.join(work, "build"))
cpp = os.path.join(work, "spring.cpp")
open(cpp, "w").write(spring)
lib = os.path.join(work, "build", "libtalus_spring.so")
p = subprocess.run([cxx, "-std=c++17", "-O1", "-fPIC", "-shared", "-Wall", "-Wextra", "-Werror",
                    "-I", os.path.join(src, "core", "include"), cpp, "-o", lib],
                   capture_output=True, text=True)
check(p.returncode == 0, "the guide's spring.cpp compiles:\n" + p.stderr[-3000:])

if cpp_test:
    test = os.path.join(work, "test_spring.cpp")
    open(test, "w").write(cpp_test[0])
    cmd = [cxx, "-std=c++17", "-fsyntax-only", "-Wall", "-Wextra", "-Werror",
           "-I", os.path.join(src, "core", "include")]
    for d in includes:
        cmd += ["-I", d]
    p = subprocess.run(cmd + [test], capture_output=True, text=True)
    check(p.returncode == 0, "the guide's C++ test compiles:\n" + p.stderr[-3000:])

if os.path.exists(lib):
    script = os.path.join(work, "guide.lua")
    open(script, "w").write("\n".join(lua))
    p = subprocess.run([talus, "run", "--quiet", script], cwd=work, capture_output=True,
                       text=True)
    check(p.returncode == 0, "the guide's Lua blocks run:\n" + p.stderr)
    # printed: the library, restitution, duration, steps, peak/overlap/rule, force and knest
    text = p.stdout
    check("libtalus_spring.so" in text, "contact_model_info names the library:\n" + text)
    lines = text.splitlines()
    try:
        restitution, duration, steps = float(lines[1]), float(lines[2]), int(lines[3])
        check(abs(restitution - 0.99995) < 5e-5, f"restitution {restitution} (guide: 0.99995)")
        check(abs(duration - 8.97e-3) < 0.01e-3, f"duration {duration} (guide: 8.97e-3 s)")
        check(steps == 30, f"steps {steps} (guide: 30)")
        force, knest = (float(x) for x in lines[5].split())
        check(abs(force - 200) < 1e-6 and knest == 1e7, f"drive: {lines[5]} (guide: 200 N, 1e7)")
    except (IndexError, ValueError) as e:
        check(False, f"the guide's printed values ({e}):\n{text}")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("guide_spring: the plugin guide compiles and runs as written")
