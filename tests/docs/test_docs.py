"""The docs name only what exists: repository paths, `make` targets and `scene.ppm` settings.

Fast, no Blender, no core: it reads the Markdown files and the repository. The rule, kept precise so
that it flags stale names and nothing else:

- Docs checked: README.md, addon/README.md, bench/README.md, docs/*.md. CHANGELOG.md is history and
  may name what no longer exists.
- Paths are looked for in inline code (`...`), fenced code blocks and link targets ([..](target)).
  In code, a word is a path when it contains a "/" and its first part is a file or folder at the
  top of the repository (`tests/...`, `docs/...`, `.github/...`) or, for a README inside a folder,
  inside that folder (`ppm_render/core.py` in addon/README.md); `../` parts resolve from the doc's
  folder. Anything else is not a path here: a bare file name (`render.py`, `scene.blend`), an
  absolute path, a URL, what is made at run time and not in the repository (`out/...`, `.venv/...`),
  a path relative to a package (`export/closure.py`). A file that no longer exists is named by its bare
  name (the old `defaults.py`).
- Not checked either: what the build makes, under a folder .gitignore names from the root (`out/`,
  `bench/out/`, `.venv/`), and the built zip's layout (NOT_IN_REPOSITORY).
- Not checked: globs and placeholders, i.e. words with `*`, `?`, `<`, `>`, `{`, `}` or `...`, or a
  part whose name is one of PLACEHOLDERS (`bench/experiments/NAME.toml`).
- Link targets are checked unless they are URLs (`scheme:`) or an anchor alone; the `#anchor` is
  dropped.
- `make TARGET ...` in code: every word after `make` up to the first that is not a target's name
  (an option, `#`, `&&`) must be a target of the Makefile.
- `scene.ppm.NAME` and `object.ppm.NAME` anywhere in a doc: NAME must be a property of
  PPMSceneSettings or PPMObjectSettings in addon/ppm_render/properties.py.
"""

import ast
import os
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ["README.md", "addon/README.md", "bench/README.md"] + sorted(
    str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))
PLACEHOLDERS = {"NAME", "N", "SCENE", "KIND", "FILE", "PATH", "VERSION", "PLATFORM", "TARGET"}
NOT_IN_REPOSITORY = {"ppm_render/lib/"}  # inside the zip that `make addon` builds
GENERATED = tuple(line.strip("/") + "/" for line in (ROOT / ".gitignore").read_text().split()
                  if line.startswith("/") and line.endswith("/"))
GLOB_OR_PLACEHOLDER = re.compile(r"[*?<>{}]|\.\.\.")
FENCE = re.compile(r"^```.*?^```", re.S | re.M)
INLINE = re.compile(r"`([^`\n]+)`")
LINK = re.compile(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
WORD = re.compile(r"[\w./*?<>{}~+-]+")
MAKE = re.compile(r"(?:^|[\s;&|(`])make((?:[ \t]+[^\s#;&|`]+)+)", re.M)
TARGET = re.compile(r"^[a-z][a-z0-9-]*$")
SETTING = re.compile(r"\b(scene|object)\.ppm\.(\w+)")


def code_of(text):
    """The doc's code: fenced blocks and inline spans (outside the blocks)."""
    blocks = FENCE.findall(text)
    return blocks + INLINE.findall(FENCE.sub("", text))


def path_words(code, doc_dir):
    """The words of `code` that the rule counts as repository paths, as (word, path from the root)."""
    top = {p.name for p in ROOT.iterdir() if p.name != ".git"}
    local = {p.name for p in (ROOT / doc_dir).iterdir()} if doc_dir != Path(".") else set()
    for word in WORD.findall(code):
        word = word.rstrip(".,")
        if ("/" not in word or word.startswith(("/", "~") + GENERATED) or word in NOT_IN_REPOSITORY
                or GLOB_OR_PLACEHOLDER.search(word)):
            continue
        parts = [p for p in word.split("/") if p]
        if any(os.path.splitext(p)[0] in PLACEHOLDERS for p in parts):
            continue
        if parts[0] == "..":
            yield word, os.path.normpath(doc_dir / word)
        elif parts[0] in top:
            yield word, os.path.normpath(word)
        elif parts[0] in local:
            yield word, os.path.normpath(doc_dir / word)


def link_targets(text, doc_dir):
    for target in LINK.findall(text):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            continue
        target = target.split("#")[0]
        if target and not GLOB_OR_PLACEHOLDER.search(target):
            yield target, os.path.normpath(doc_dir / target)


def make_targets():
    names = set()
    for line in (ROOT / "Makefile").read_text().splitlines():
        m = re.match(r"^([\w.%/ -]+?)\s*:(?!=)", line)
        if m:
            names.update(m.group(1).split())
    return names


def settings():
    tree = ast.parse((ROOT / "addon/ppm_render/properties.py").read_text())
    found = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            found[node.name] = {s.target.id for s in node.body
                                if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name)}
    return {"scene": found["PPMSceneSettings"], "object": found["PPMObjectSettings"]}


def stale_names(doc, text=None):
    """Every name in `doc` (its text, or `text`) that does not exist, as readable strings."""
    text = (ROOT / doc).read_text() if text is None else text
    doc_dir = Path(doc).parent
    stale = []
    for code in code_of(text):
        stale += [f"path `{w}`" for w, p in path_words(code, doc_dir) if not (ROOT / p).exists()]
        for m in MAKE.finditer(code):
            for word in m.group(1).split():
                if not TARGET.match(word):
                    break
                if word not in make_targets():
                    stale.append(f"make target `{word}`")
    stale += [f"link ({w})" for w, p in link_targets(text, doc_dir) if not (ROOT / p).exists()]
    known = settings()
    stale += [f"setting `{kind}.ppm.{name}`" for kind, name in SETTING.findall(text) if name not in known[kind]]
    return sorted(set(stale))


@pytest.mark.parametrize("doc", DOCS)
def test_doc_names_only_what_exists(doc):
    assert stale_names(doc) == [], f"{doc} names what does not exist"


def test_the_check_finds_stale_names():
    text = ("`tests/blenders/no_such_compare.py`, [x](docs/NO_SUCH.md), `make no-such-target`, "
            "`scene.ppm.no_such_setting`\n```sh\nmake demo\n.venv/bin/python tools/no_such_tool.py\n```\n")
    assert stale_names("README.md", text) == [
        "link (docs/NO_SUCH.md)", "make target `no-such-target`", "path `tests/blenders/no_such_compare.py`",
        "path `tools/no_such_tool.py`", "setting `scene.ppm.no_such_setting`"]


def test_the_check_leaves_what_is_not_a_path():
    text = ("`out/ppm_render-0.1.0-linux-x64.zip`, `bench/experiments/NAME.toml`, `render.py`, "
            "`https://example.org/a/b`, `blend_scenes/*.blend`, `/path/ppm.zip`, `export/closure.py`, "
            "`.venv/bin/python`, [anchor](#settings), [site](https://www.blender.org/x), `make demo`\n")
    assert stale_names("README.md", text) == []


def test_make_demo_installs_only_what_the_demo_needs():
    """`make demo` sets up one environment and one core (tools/setup.sh --demo), not the test matrix:
    the commands make would run for it from scratch (-n -B: print them all, run none)."""
    run = subprocess.run(["make", "-n", "-B", "demo"], cwd=ROOT, capture_output=True, text=True, check=True)
    commands = [line.strip() for line in run.stdout.splitlines()]
    assert "tools/setup.sh --demo" in commands
    assert any(c.endswith("tools/build_cores.sh --demo") for c in commands)
    assert any("render.py blend_scenes/cornell_3spheres.blend" in c for c in commands)
    assert not any(c == "tools/setup.sh" or ".venvs" in c or "pytest" in c for c in commands), commands
