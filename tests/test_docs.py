"""The README and the manual (``docs/*.md``) say what the code does: their code runs.

Each page runs in its own process, in a fresh temporary folder that holds links to the
repository's ``scenarios/``, ``models/`` and ``benchmarks/``, a copy of ``docs/`` and an
empty ``runs/`` (so repository-relative paths work and nothing is written into the
checkout; ``.ci/run`` runs the README's main command on a fresh clone):

- ```` ```python ```` blocks run in order, in one namespace per page;
- ```` ```bash ```` blocks run their commands, which must be ``twsb``, ``pvfilter`` or
  ``python`` (this checkout's code, through ``PYTHONPATH``), and must exit with 0; a
  ``pip install`` step is passed over, as the test runs in an installed environment;
  ``> FILE`` sends a command's output to a file;
- a block right after ``<!-- not run: REASON -->`` is not run, so every skip is explicit
  and says why; any other command in a bash block is an error;
- a ```` ```text ```` block right after ``<!-- expected output (timings vary) -->`` must
  be what the last command printed, timings aside.

Run as ``python -m tests.test_docs PAGE FOLDER``, this module runs one page. The other
tests check the links between pages and the tables that restate the code.
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import types
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
PAGES = [README, *sorted((ROOT / "docs").glob("*.md"))]
LINKED_PAGES = [*PAGES, ROOT / "docs" / "results" / "README.md"]
# pages of the manual written alongside these: links to them are checked once they exist
PAGES_IN_PROGRESS = {"docs/robustness.md", "docs/sensors.md", "docs/envelope.md", "docs/stress.md"}
README_MAX_LINES = 300

FENCE = re.compile(r"^```(\w*)\s*$")
NOT_RUN = re.compile(r"^<!--\s*not run:(.*?)-->$")
EXPECTED_OUTPUT = "<!-- expected output (timings vary) -->"
TIMINGS = (
    re.compile(r"in [\d.]+ s wall \([\d.]+x real time\)"),
    re.compile(r"[\d,.]+ scans/s"),
)
SHELLS = {"bash", "sh", "shell"}
LINKED_FOLDERS = ("scenarios", "models", "benchmarks")
COMMAND_TIMEOUT_S = 300.0
PAGE_TIMEOUT_S = 900.0
PARALLEL_PAGES = 2  # the suite's target machine has 2 cores


@dataclasses.dataclass(frozen=True)
class Block:
    """A fenced code block of a page.

    Attributes:
        language: the fence's info string (``python``, ``bash``, ``text``, ...).
        code: the block's text.
        line: the page's line number of the first line of code (1-based).
        marker: the HTML comment on the last non-blank line before the fence, "" if none.
    """

    language: str
    code: str
    line: int
    marker: str

    @property
    def skip_reason(self) -> str | None:
        """Why the block is not run, or None."""
        match = NOT_RUN.match(self.marker)
        return match.group(1).strip() if match else None


class DocsError(Exception):
    """A page's code does not do what the page says."""


def blocks(page: Path) -> list[Block]:
    """The page's fenced code blocks, in order."""
    lines = page.read_text(encoding="utf-8").splitlines()
    found, k = [], 0
    while k < len(lines):
        fence = FENCE.match(lines[k])
        if not fence:
            k += 1
            continue
        before = [line.strip() for line in lines[:k] if line.strip()]
        marker = before[-1] if before and before[-1].startswith("<!--") else ""
        end = next((j for j in range(k + 1, len(lines)) if lines[j].startswith("```")), None)
        if end is None:
            raise DocsError(f"{page.name}:{k + 1}: a code block that never closes")
        found.append(Block(fence.group(1), "\n".join(lines[k + 1 : end]), k + 2, marker))
        k = end + 1
    return found


def shell_commands(code: str) -> list[list[str]]:
    """The commands of a bash block: lines joined at ``\\``, split at ``&&``, comments off."""
    commands = []
    for line in code.replace("\\\n", " ").splitlines():
        tokens = shlex.split(line, comments=True)
        while tokens:
            end = tokens.index("&&") if "&&" in tokens else len(tokens)
            commands.append(tokens[:end])
            tokens = tokens[end + 1 :]
    return commands


def argv_of(tokens: list[str], where: str) -> list[str] | None:
    """How the test runs a command: None for a step it passes over.

    Raises:
        DocsError: a command the test cannot run (it needs a not-run marker).
    """
    program, args = tokens[0], tokens[1:]
    if program in ("pip", "pip3"):
        return None  # the test runs in an environment where the project is installed
    if program == "twsb":
        return [sys.executable, "-m", "twsb_sim.cli", *args]
    if program == "pvfilter":
        return [sys.executable, "-m", "pvfilter.cli", *args]
    if program in ("python", "python3"):
        return [sys.executable, *args]
    raise DocsError(
        f"{where}: runs {program!r}; the test runs twsb, pvfilter and python only: "
        "put <!-- not run: REASON --> right before the block"
    )


def run_command(tokens: list[str], where: str, environment: dict[str, str]) -> str:
    """Run one command of a bash block and return what it printed on stdout."""
    for operator in ("|", ";", "<", ">>", "2>"):
        if operator in tokens:
            raise DocsError(f"{where}: {operator!r} in {shlex.join(tokens)}: not supported")
    output_file = None
    if ">" in tokens:
        at = tokens.index(">")
        tokens, output_file = tokens[:at] + tokens[at + 2 :], tokens[at + 1]
    argv = argv_of(tokens, where)
    if argv is None:
        return ""
    done = subprocess.run(
        argv, capture_output=True, text=True, env=environment, timeout=COMMAND_TIMEOUT_S
    )
    if done.returncode != 0:
        raise DocsError(
            f"{where}: `{shlex.join(tokens)}` exited with {done.returncode}\n"
            f"{done.stdout[-2000:]}{done.stderr[-3000:]}"
        )
    if output_file is not None:
        Path(output_file).write_text(done.stdout, encoding="utf-8")
        return ""
    return done.stdout


def without_timings(text: str) -> list[str]:
    """The lines of a command's output with its timings blanked out."""
    lines = []
    for line in text.strip().splitlines():
        for timing in TIMINGS:
            line = timing.sub("<timing>", line)
        lines.append(line.rstrip())
    return lines


def prepare_folder(folder: Path) -> None:
    """A working folder in which the pages' repository-relative paths work."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in LINKED_FOLDERS:
        (folder / name).symlink_to(ROOT / name, target_is_directory=True)
    ignore = shutil.ignore_patterns("__pycache__")
    shutil.copytree(ROOT / "docs", folder / "docs", ignore=ignore)
    (folder / "runs").mkdir()


def environment() -> dict[str, str]:
    """The commands' environment: this checkout's code, no usage data, no display."""
    path = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p)
    return {**os.environ, "PYTHONPATH": path, "CI": "1", "MPLBACKEND": "Agg"}


def run_page(page: Path, folder: Path) -> None:
    """Run the code of one page in ``folder`` (see the module docstring).

    Raises:
        DocsError: the first block that fails, with the page and line.
    """
    prepare_folder(folder)
    os.chdir(folder)
    env = environment()
    module = types.ModuleType("__docs__")  # a real module: dataclasses look classes up
    sys.modules[module.__name__] = module
    namespace: dict[str, Any] = module.__dict__
    last_output = None
    name = page.relative_to(ROOT).as_posix()
    for block in blocks(page):
        where = f"{name}:{block.line}"
        if block.marker.startswith("<!-- not run") and not block.skip_reason:
            raise DocsError(f"{where}: a not-run marker must say why")
        if block.skip_reason is not None:
            continue
        if block.language == "python":
            code = "\n" * (block.line - 1) + block.code  # tracebacks show the page's lines
            exec(compile(code, name, "exec"), namespace)
        elif block.language in SHELLS:
            for tokens in shell_commands(block.code):
                last_output = run_command(tokens, where, env)
        elif block.marker == EXPECTED_OUTPUT:
            if last_output is None:
                raise DocsError(f"{where}: expected output, but no command ran before it")
            expected, printed = without_timings(block.code), without_timings(last_output)
            if expected != printed:
                raise DocsError(
                    f"{where}: the command printed something else:\n" + "\n".join(printed)
                )


def main(argv: list[str]) -> int:
    """Entry point of ``python -m tests.test_docs PAGE FOLDER``."""
    page, folder = Path(argv[0]).resolve(), Path(argv[1])
    try:
        run_page(page, folder)
    except DocsError as error:
        print(error, file=sys.stderr)
        return 1
    return 0


def _page_id(page: Path) -> str:
    return page.relative_to(ROOT).as_posix()


def _run_page_process(page: Path, folder: Path) -> subprocess.CompletedProcess:
    argv = [sys.executable, "-m", "tests.test_docs", str(page), str(folder)]
    return subprocess.run(
        argv, capture_output=True, text=True, env=environment(), timeout=PAGE_TIMEOUT_S
    )


@pytest.fixture(scope="module")
def page_runs(request, tmp_path_factory) -> dict[str, Future]:
    """The selected pages' runs, started together, ``PARALLEL_PAGES`` at a time."""
    selected = [
        item.callspec.params["page"]
        for item in request.session.items
        if item.originalname == "test_code_of_the_page_runs" and hasattr(item, "callspec")
    ]
    pool = ThreadPoolExecutor(max_workers=PARALLEL_PAGES)
    runs = {
        _page_id(page): pool.submit(
            _run_page_process, page, tmp_path_factory.mktemp("docs") / page.stem
        )
        for page in selected
    }
    yield runs
    pool.shutdown(wait=True, cancel_futures=True)


@pytest.mark.parametrize("page", PAGES, ids=_page_id)
def test_code_of_the_page_runs(page, page_runs):
    done = page_runs[_page_id(page)].result()
    assert done.returncode == 0, done.stderr[-6000:] + done.stdout[-2000:]


def test_every_skip_says_why_and_is_rare():
    skipped = [(page.name, b.line) for page in PAGES for b in blocks(page) if b.skip_reason]
    runnable = [b for page in PAGES for b in blocks(page) if b.language in {"python", *SHELLS}]
    assert all(b.skip_reason for page in PAGES for b in blocks(page) if "not run" in b.marker)
    assert 4 * len(skipped) <= len(runnable), skipped  # at most one block in four


def test_readme_is_a_short_door_with_the_two_commands_first():
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= README_MAX_LINES
    quick_start = text.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    shell = re.findall(r"```bash\n(.*?)```", quick_start, flags=re.S)  # as .ci/run reads them
    assert shell[0].strip() == (
        "pip install -e . && twsb run hard_stop --rrd runs/hard_stop.rrd --out runs/hard_stop"
    )
    assert shell[1].strip() == 'pip install -e ".[test]" && python -m pytest'


# links ------------------------------------------------------------------------------------

LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def _prose(page: Path) -> str:
    """The page without its fenced code blocks."""
    return re.sub(r"^```.*?^```", "", page.read_text(encoding="utf-8"), flags=re.S | re.M)


def heading_anchors(page: Path) -> set[str]:
    """The anchors a git host gives the page's headings."""
    anchors, seen = set(), {}
    for heading in re.findall(r"^#{1,6} (.+)$", _prose(page), flags=re.M):
        slug = re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")
        count = seen.get(slug, 0)
        seen[slug] = count + 1
        anchors.add(slug if count == 0 else f"{slug}-{count}")
    return anchors


@pytest.mark.parametrize("page", LINKED_PAGES, ids=_page_id)
def test_links_point_at_files_and_headings_that_exist(page):
    broken = []
    for target in LINK.findall(_prose(page)):
        if re.match(r"^[a-z]+:", target):
            continue  # https:, mailto:
        path, _, anchor = target.partition("#")
        resolved = (page.parent / path).resolve() if path else page
        if resolved.relative_to(ROOT).as_posix() in PAGES_IN_PROGRESS and not resolved.exists():
            continue
        if not resolved.exists():
            broken.append(target)
        elif anchor and resolved.suffix == ".md" and anchor not in heading_anchors(resolved):
            broken.append(target)
    assert not broken, f"{page.name}: {broken}"


# tables that restate the code ---------------------------------------------------------------


def table_rows(page: Path, header: tuple[str, ...]) -> list[dict[str, str]]:
    """The rows of the page's table whose header starts with ``header``."""
    lines = page.read_text(encoding="utf-8").splitlines()
    for k, line in enumerate(lines):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if tuple(cells[: len(header)]) != header:
            continue
        rows = []
        for row in lines[k + 2 :]:
            if not row.startswith("|"):
                break
            values = [c.strip() for c in row.strip().strip("|").split("|")]
            rows.append(dict(zip(cells, values, strict=True)))
        return rows
    raise AssertionError(f"{page.name}: no table headed {header}")


def split_top_level(text: str) -> list[str]:
    """Split at commas outside brackets: ``"[1, 2], 3"`` -> ``["[1, 2]", "3"]``."""
    parts, depth, start = [], 0, 0
    for k, char in enumerate(text):
        depth += {"[": 1, "]": -1}.get(char, 0)
        if char == "," and depth == 0:
            parts.append(text[start:k].strip())
            start = k + 1
    return [*parts, text[start:].strip()]


def documented_defaults(page: Path, header: tuple[str, ...], name: str, default: str):
    """``{field: value}`` from a table listing fields (in backticks) and their defaults."""
    values = {}
    for row in table_rows(page, header):
        names = re.findall(r"`([^`]+)`", row[name])
        defaults = split_top_level(row[default])
        if len(defaults) == 1:  # one default for every field of the row
            defaults *= len(names)
        assert len(names) == len(defaults), row
        for field, value in zip(names, defaults, strict=True):
            values[field] = json.loads(value)
    return values


def _same(documented, actual) -> bool:
    if isinstance(actual, (list, tuple)):
        return list(documented) == pytest.approx(list(actual))
    return documented == pytest.approx(actual)


def test_data_set_ranges_table_is_the_generator_defaults():
    from twsb_sim.dataset import Randomization

    documented = documented_defaults(
        ROOT / "docs" / "datasets.md", ("key", "default", "meaning"), "key", "default"
    )
    actual = {
        f"{section}.{key}": value
        for section, table in Randomization().to_dict().items()
        for key, value in table.items()
    }
    assert set(documented) == set(actual)
    wrong = {k: (documented[k], actual[k]) for k in actual if not _same(documented[k], actual[k])}
    assert not wrong


def test_data_set_schema_table_is_the_schema():
    from twsb_sim.dataset import COLUMNS

    arrow_names = {"double": "float64", "float": "float32", "list<item: float>": "list<float32>"}
    arrow_names["list<item: uint8>"] = "list<uint8>"
    arrow_names["list<item: double>"] = "list<float64>"
    documented = {}
    for row in table_rows(ROOT / "docs" / "datasets.md", ("column", "type", "meaning")):
        for column in re.findall(r"`([^`]+)`", row["column"]):
            documented[column] = row["type"].replace("\\", "")
    actual = {name: arrow_names.get(str(kind), str(kind)) for name, kind, _ in COLUMNS}
    assert documented == actual


@pytest.mark.parametrize(
    ("page", "header", "params"),
    [
        ("improved_filter.md", ("field", "default"), "ImprovedParams"),
        ("paper_filter.md", ("paper", "field", "default"), "FilterParams"),
    ],
)
def test_parameter_tables_are_the_defaults(page, header, params):
    import pvfilter

    documented = documented_defaults(ROOT / "docs" / page, header, "field", "default")
    actual = dataclasses.asdict(getattr(pvfilter, params)())
    actual = {k: v for k, v in actual.items() if k not in ("clustering", "tracking")}
    assert set(documented) == set(actual)
    assert all(_same(documented[k], v) for k, v in actual.items()), documented


def test_the_sensor_effects_table_is_the_command_s_output():
    """docs/sensors.md's table of what each imperfection does to the paper's filter holds
    the figures ``docs/sensor_effects.py`` wrote to ``docs/results/sensor_effects.txt``."""
    written = {}
    for line in (ROOT / "docs" / "results" / "sensor_effects.txt").read_text().splitlines():
        match = re.match(r"^(.*?)\s+(\d+)\s+(\d+)\s+(\d+)$", line)
        if match:
            written[match[1].strip()] = list(match.groups()[1:])
    header = ("sensors", "beams removed", "of them pitch-variation", "pitch-variation beams")
    rows = table_rows(ROOT / "docs" / "sensors.md", header)
    assert len(rows) == len(written) == 12
    for row in rows:
        figures = [row[name] for name in header[1:]]
        assert written[row["sensors"].replace("°", " deg")] == figures, row["sensors"]


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
