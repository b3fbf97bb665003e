"""The documentation stays true: README.md and docs/*.md are checked against
the build.

- Every ```sh and ```python block runs as written, in document order, from a
  copy of the repository's layout (examples/, build/release/cli/invmap,
  build/release/python) in a temporary directory: sh blocks with bash -e,
  each python block saved as a script and run by this interpreter (so the
  Dask example runs as a user's script does, worker processes re-importing
  it). A block preceded by a line "<!-- not run by the docs test: why -->"
  is skipped (set-up commands, servers).
- ```cpp blocks: docs/library.md holds the code of examples/api_example.cpp
  whole (comments aside), which the suite builds and runs; any other
  complete program (one with main) compiles against include/ alone; a block
  without main is an excerpt of that example (its code lines appear there in
  order).
- Relative links point to files that exist, #anchors to their headings, and
  `paths` into the repository's folders exist.
- Every subcommand of `invmap --help` has a section titled `invmap <name>`
  on some page, naming every option its --help lists and no other.
- Nothing points outside the repository.
"""

import os
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

import invmap
from conftest import REPO

PAGES = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
SKIP_MARK = "<!-- not run by the docs test"
API_EXAMPLE = REPO / "examples" / "api_example.cpp"


class Block:
    """A fenced code block: its language, text and first line (1-based, the fence)."""

    def __init__(self, page, line, lang, text, skipped):
        self.page, self.line, self.lang, self.text, self.skipped = page, line, lang, text, skipped

    def where(self):
        return f"{self.page.relative_to(REPO)}:{self.line}"


def blocks(page):
    lines = page.read_text(encoding="utf-8").splitlines()
    found, i = [], 0
    while i < len(lines):
        match = re.match(r"^```(\S*)\s*$", lines[i])
        if not match:
            i += 1
            continue
        start, body = i, []
        i += 1
        while i < len(lines) and lines[i].rstrip() != "```":
            body.append(lines[i])
            i += 1
        previous = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
        found.append(Block(page, start + 1, match.group(1), "\n".join(body) + "\n",
                           previous.strip().startswith(SKIP_MARK)))
        i += 1
    return found


def runnable(page):
    return [b for b in blocks(page) if b.lang in ("sh", "python") and not b.skipped]


def cli_path():
    if os.environ.get("INVMAP_CLI"):
        return pathlib.Path(os.environ["INVMAP_CLI"])
    return pathlib.Path(invmap.__file__).resolve().parents[2] / "cli" / "invmap"


@pytest.fixture()
def sandbox(tmp_path):
    """The repository's layout as the docs assume it, outputs kept out of the source tree."""
    cli = cli_path()
    if not cli.is_file():
        pytest.skip(f"the invmap command is not built ({cli}); set INVMAP_CLI")
    root = tmp_path / "repo"
    (root / "build" / "release" / "cli").mkdir(parents=True)
    (root / "examples").symlink_to(REPO / "examples")
    (root / "build" / "release" / "cli" / "invmap").symlink_to(cli)
    (root / "build" / "release" / "python").symlink_to(pathlib.Path(invmap.__file__).resolve().parents[1])
    return root


@pytest.mark.parametrize("page", [p for p in PAGES if runnable(p)], ids=lambda p: str(p.relative_to(REPO)))
def test_examples_run_as_written(page, sandbox):
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1",
               PATH=f"{sandbox}/build/release/cli{os.pathsep}{os.environ.get('PATH', '')}",
               PYTHONPATH=str(sandbox / "build" / "release" / "python"))
    for block in runnable(page):
        if block.lang == "sh":
            command = ["bash", "-e", "-o", "pipefail", "-c", block.text]
        else:
            script = sandbox / f"example_{page.stem}_{block.line}.py"
            script.write_text(block.text, encoding="utf-8")
            command = [sys.executable, str(script)]
        try:
            done = subprocess.run(command, cwd=sandbox, env=env, capture_output=True, text=True, timeout=120)
        except subprocess.TimeoutExpired as timeout:
            pytest.fail(f"{block.where()}: the {block.lang} block ran for more than {timeout.timeout} s "
                        f"(a Dask script without its __main__ guard hangs so)\n--- stderr\n{timeout.stderr}")
        assert done.returncode == 0, (f"{block.where()}: the {block.lang} block failed (exit {done.returncode})\n"
                                      f"--- stdout\n{done.stdout}\n--- stderr\n{done.stderr}")


def code_lines(text):
    """The C++ lines without comments (which may be worded differently in a page)."""
    lines = (re.sub(r"\s*//.*$", "", line).rstrip() for line in text.splitlines())
    return [line.strip() for line in lines if line.strip()]


def test_cpp_blocks_compile_or_quote_the_built_example(tmp_path):
    example = code_lines(API_EXAMPLE.read_text(encoding="utf-8"))
    compiler = shutil.which("c++") or shutil.which("g++") or shutil.which("clang++")
    cpp = [b for page in PAGES for b in blocks(page) if b.lang == "cpp"]
    quoted = [b for b in cpp if code_lines(b.text) == example]
    assert any(b.page.name == "library.md" for b in quoted), \
        "docs/library.md must hold the code of examples/api_example.cpp whole"
    for block in cpp:
        if block in quoted:
            continue
        if "int main(" in block.text:
            if compiler is None:
                continue
            source = tmp_path / f"{block.page.stem}_{block.line}.cpp"
            source.write_text(block.text, encoding="utf-8")
            done = subprocess.run([compiler, "-std=c++17", "-fsyntax-only", f"-I{REPO / 'include'}", str(source)],
                                  capture_output=True, text=True, timeout=120)
            assert done.returncode == 0, f"{block.where()}: does not compile\n{done.stderr}"
        else:
            position = 0
            for line in code_lines(block.text):
                try:
                    position = example.index(line, position) + 1
                except ValueError:
                    pytest.fail(f"{block.where()}: '{line}' is not in examples/api_example.cpp (in this order)")


def slug(heading):
    """The anchor GitHub gives a heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def prose(page):
    """The page without its code blocks (whose lines may start with # too)."""
    return re.sub(r"^```.*?^```$", "", page.read_text(encoding="utf-8"), flags=re.M | re.S)


def anchors(page):
    return {slug(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", prose(page), re.M)}


def test_links_resolve():
    for page in PAGES:
        text = prose(page)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", target):
                continue
            path, _, anchor = target.partition("#")
            file = (page.parent / path).resolve() if path else page
            assert file.exists(), f"{page.relative_to(REPO)}: link to {target}: no such file"
            assert REPO in file.parents or file == REPO, f"{page.relative_to(REPO)}: {target} leaves the repository"
            if anchor and file.suffix == ".md":
                assert anchor in anchors(file), f"{page.relative_to(REPO)}: link to {target}: no such heading"


def test_paths_into_the_repository_exist():
    folders = {p.name for p in REPO.iterdir() if p.is_dir() and p.name not in ("build", "out", ".git")}
    for page in PAGES:
        for span in re.findall(r"`([^`\s]+)`", prose(page)):
            path = span.rstrip(".,:;")
            if "/" in path and path.split("/")[0] in folders and not re.search(r"[<>*]", path):
                assert (REPO / path).exists(), f"{page.relative_to(REPO)}: `{span}` does not exist"


def sections(page):
    """(heading, its prose up to the next heading of the same or a higher level)."""
    text = prose(page)
    heads = [(m.start(), len(m.group(1)), m.group(2)) for m in re.finditer(r"^(#+)\s+(.*)$", text, re.M)]
    for k, (start, level, title) in enumerate(heads):
        end = next((s for s, l, _ in heads[k + 1:] if l <= level), len(text))
        yield title, text[start:end]


def long_options(help_text):
    return set(re.findall(r"(?<![\w-])--[a-z][a-z-]*", help_text)) - {"--help", "--version"}


def test_every_command_and_option_is_documented(sandbox):
    cli = str(sandbox / "build" / "release" / "cli" / "invmap")
    top = subprocess.run([cli, "--help"], capture_output=True, text=True, check=True).stdout
    commands = re.findall(r"^  (\w+)\s", top.split("Subcommands:", 1)[1], re.M)
    assert "invert" in commands
    documented = {}
    for page in PAGES:
        for title, text in sections(page):
            match = re.fullmatch(r"`invmap (\w+)`", title.strip())
            if match:
                documented.setdefault(match.group(1), []).append((page, text))
    for command in commands:
        assert command in documented, f"`invmap {command}` has no section titled `invmap {command}` in the docs"
        options = long_options(subprocess.run([cli, command, "--help"], capture_output=True, text=True,
                                              check=True).stdout)
        for page, text in documented[command]:
            named = long_options(text)
            where = f"{page.relative_to(REPO)}, section `invmap {command}`"
            assert options <= named, f"{where}: undocumented options {sorted(options - named)}"
            assert named <= options, f"{where}: options the command does not have {sorted(named - options)}"


def test_nothing_points_outside_the_repository():
    outside = re.compile(r"FORMATS\.md|DESIGN\.md|STYLE\.md|\.\./shared|/work/|(?i:\bthe seeds?\b)")
    for page in PAGES:
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            assert not outside.search(line), f"{page.relative_to(REPO)}:{number}: points outside: {line.strip()}"
