#!/usr/bin/env python3
"""The documentation as one source of truth (CTest test `docs`).

Checks, with the standard library only:
  - every relative link and #anchor of README.md, CONTRIBUTING.md and
    docs/*.md resolves (GitHub's anchor rules); http(s) links are skipped;
  - README.md is at most 250 lines;
  - the README's first two code blocks are its two commands (install, build
    and run; scripts/test.sh), and scripts/test.sh is what .ci/run runs;
  - for every command of the CLI (found from `fssim --help` and the
    subcommands each help lists), every long option its help lists is a row
    of the options table of the one docs/*.md section whose heading names
    the command (`fssim code analyze`; `fssim --input` for the simulation)
    and a .TP entry of the man page's (docs/fssim.1) .SS section of the
    command, with the default the help shows; and neither lists an option
    the help does not.

Environment: FSSIM (the binary; default build/fssim), FSS_SOURCE_DIR (the
checkout; default two levels above this file).
"""
import os
import re
import subprocess
import unittest
from pathlib import Path

SOURCE = Path(os.environ.get("FSS_SOURCE_DIR") or Path(__file__).resolve().parents[2])
FSSIM = os.environ.get("FSSIM") or str(SOURCE / "build" / "fssim")
README_MAX_LINES = 250


def rel(path):
    """A path as the messages name it: relative to the checkout."""
    try:
        return str(Path(path).relative_to(SOURCE))
    except ValueError:
        return str(path)


def markdown_files():
    files = [SOURCE / "README.md", SOURCE / "CONTRIBUTING.md"]
    files += sorted((SOURCE / "docs").glob("*.md"))
    return files


# ---------------------------------------------------------------- markdown


def read_lines(path):
    return path.read_text(encoding="utf-8").split("\n")


def prose_lines(lines):
    """(line number, text) of the lines outside fenced code blocks."""
    fence = None
    for number, line in enumerate(lines, 1):
        match = re.match(r"^\s*(```+|~~~+)", line)
        if match:
            marker = match.group(1)
            if fence is None:
                fence = marker[0] * len(marker)
            elif marker.startswith(fence):
                fence = None
            continue
        if fence is None:
            yield number, line


def code_blocks(lines):
    """The contents of the fenced code blocks, in order."""
    blocks, current, fence = [], None, None
    for line in lines:
        match = re.match(r"^\s*(```+|~~~+)", line)
        if match:
            marker = match.group(1)
            if fence is None:
                fence, current = marker[0] * len(marker), []
                continue
            if marker.startswith(fence):
                blocks.append("\n".join(current))
                fence, current = None, None
                continue
        if current is not None:
            current.append(line)
    return blocks


def blank_code_spans(text):
    """The text with inline code spans replaced by spaces (same length)."""
    return re.sub(r"(`+)(.+?)\1", lambda m: " " * len(m.group(0)), text)


def headings(lines):
    """(line number, level, text) of the ATX headings outside code blocks."""
    result = []
    for number, line in prose_lines(lines):
        match = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
        if match:
            result.append((number, len(match.group(1)), match.group(2)))
    return result


def github_anchor(heading_text):
    """The anchor GitHub gives a heading: its text, lowercased, punctuation
    dropped, spaces turned into hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading_text)  # links: their text
    text = text.replace("`", "").replace("*", "")
    text = text.lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors_of(path):
    anchors, seen = set(), {}
    for _, _, text in headings(read_lines(path)):
        anchor = github_anchor(text)
        count = seen.get(anchor, 0)
        seen[anchor] = count + 1
        anchors.add(anchor if count == 0 else f"{anchor}-{count}")
    return anchors


LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")


def links_of(path):
    """(line number, target) of every inline link and image."""
    for number, line in prose_lines(read_lines(path)):
        for match in LINK.finditer(blank_code_spans(line)):
            yield number, match.group(1)


def table_blocks(lines):
    """Tables in `lines` (number, text) pairs: lists of (line number, cells),
    the header first, the separator row left out."""
    tables, current = [], []
    for number, line in lines:
        if line.lstrip().startswith("|"):
            current.append((number, split_row(line)))
            continue
        if current:
            tables.append(current)
            current = []
    if current:
        tables.append(current)
    result = []
    for table in tables:
        if len(table) >= 2 and all(re.fullmatch(r":?-+:?", c.strip()) for c in table[1][1] if c.strip()):
            result.append([table[0]] + table[2:])
    return result


def split_row(line):
    line = line.strip()
    if line.startswith("|"):
        line = line[1:]
    if line.endswith("|") and not line.endswith("\\|"):
        line = line[:-1]
    return [cell.strip() for cell in re.split(r"(?<!\\)\|", line)]


# ---------------------------------------------------------------- the help


class Option:
    def __init__(self, names, default, description):
        self.names = names  # e.g. ["-c", "--code"]
        self.default = default  # None, or the default the help shows
        self.description = description

    @property
    def long_names(self):
        return [n for n in self.names if n.startswith("--")]


def run_help(path):
    result = subprocess.run([FSSIM, *path, "--help"], capture_output=True, text=True, timeout=60)
    if result.returncode != 0:
        raise AssertionError(f"fssim {' '.join(path)} --help exited {result.returncode}: {result.stderr}")
    return result.stdout


TEXT_DEFAULT = re.compile(r"\bdefault\b:?\s+([^,;:()]+?)\s*(?=[,;:()]|$)")


def parse_help(text):
    """(options, subcommand names) of one --help text (CLI11's layout: the
    description starts at column 32, or on the next line when the option's
    name and type are longer)."""
    options, subcommands, section = [], [], None
    lines = text.split("\n")
    for index, line in enumerate(lines):
        if re.match(r"^[A-Z][A-Za-z]*:$", line):
            section = line[:-1]
            continue
        if section == "Subcommands":
            match = re.match(r"^  (\S+)", line)
            if match:
                subcommands.append(match.group(1))
            continue
        if section != "Options" or not re.match(r"^  -", line):
            continue
        following = lines[index + 1] if index + 1 < len(lines) else ""
        if re.match(r"^ {30,}\S", following):  # the description is on the next line
            spec, description = line.strip(), following.strip()
        else:
            spec, description = line[:32].strip(), line[32:].strip()
        tokens = spec.split()
        names = [re.sub(r"\{[^}]*\}$", "", n) for n in tokens[0].split(",")]
        default = None
        for token in tokens[1:]:
            match = re.search(r"=(\S+)$", token)
            if match:
                default = match.group(1)
        if default is None:
            match = TEXT_DEFAULT.search(description)
            if match:
                default = match.group(1).strip()
        options.append(Option(names, default, description))
    return options, subcommands


def commands():
    """[(path, options)] of every command, the simulation ([]) first."""
    found, queue = [], [[]]
    while queue:
        path = queue.pop(0)
        options, subcommands = parse_help(run_help(path))
        found.append((path, options))
        queue.extend(path + [name] for name in subcommands)
    return found


def command_name(path):
    return "fssim " + (" ".join(path) if path else "--input")


def help_command(path):
    return " ".join(["fssim", *path, "--help"])


def names_command(words, path):
    """True when `words` (of a heading's code span or a man page's .SS
    title) name the command `path`: `fssim PATH`, then nothing, an option,
    a bracket or an argument in capitals; for the simulation `fssim --...`."""
    head = ["fssim"] + path
    if words[: len(head)] != head:
        return False
    rest = words[len(head):]
    if not path:
        return bool(rest) and rest[0].startswith("-")
    return not rest or rest[0][0] in "-[" or rest[0][0].isupper()


def option_pattern(name):
    return re.compile(r"(?<![\w-])" + re.escape(name) + r"(?![\w-])")


def long_options_in(text):
    return set(re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", text))


def normalize(text):
    text = text.replace("`", "").replace("*", "").replace("\u2212", "-").replace("\\|", "|")
    return re.sub(r"\s+", " ", text).strip().lower()


NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def as_number(text):
    return float(text) if NUMBER.fullmatch(text) else None


def states_default(text, default):
    """True when `text` (a docs table cell, or what follows "Default:" in the
    man page) starts with the default: the same number, or the same words."""
    text = normalize(text)
    number = as_number(default)
    if number is not None:
        match = NUMBER.match(text)
        return match is not None and float(match.group(0)) == number
    return re.match(re.escape(normalize(default)) + r"(?![\w-])", text) is not None


# ---------------------------------------------------------------- man page


TROFF_NAMES = {"*a": "α", "*S": "Σ", "*p": "π", "mu": "×", "em": "-", "en": "-", ">=": "≥",
               "<=": "≤", "sc": "§", "aa": "'"}


def troff_arguments(text):
    args, current, quoted, i = [], "", False, 0
    while i < len(text):
        c = text[i]
        if quoted and c == '"' and text[i + 1: i + 2] == '"':
            current += '"'
            i += 2
            continue
        if c == '"':
            quoted = not quoted
        elif c == " " and not quoted:
            if current:
                args.append(current)
            current = ""
        else:
            current += c
        i += 1
    if current:
        args.append(current)
    return args


def troff_text(line):
    """The text a line of troff shows (font macros joined, escapes resolved)."""
    if line.startswith(".\\\""):
        return ""
    if line.startswith("."):
        macro, _, rest = line.partition(" ")
        args = troff_arguments(rest)
        if macro in (".B", ".I", ".SM", ".SB", ".SS", ".SH"):
            line = " ".join(args)
        elif macro in (".BR", ".RB", ".BI", ".IB", ".IR", ".RI"):
            line = "".join(args)
        else:
            return ""
    line = re.sub(r"\\f[BIRP]", "", line)
    line = re.sub(r"\\\((..)", lambda m: TROFF_NAMES.get(m.group(1), ""), line)
    line = line.replace("\\-", "-").replace("\\~", " ").replace("\\|", "").replace("\\&", "")
    line = line.replace("\\e", "\\")
    return line


def man_sections(path):
    """{title: [lines]} of the .SS sections of the man page."""
    sections, current = {}, None
    for line in read_lines(path):
        if line.startswith(".SS ") or line.startswith(".SH "):
            current = None
            if line.startswith(".SS "):
                current = troff_text(line)
                sections[current] = []
            continue
        if current is not None:
            sections[current].append(line)
    return sections


def man_entries(lines):
    """[(tag text, paragraph text)] of the .TP entries of a section."""
    entries, tag, body, state = [], None, [], None
    for line in lines + [".PP"]:
        if line.startswith((".TP", ".PP", ".SS", ".SH", ".RS", ".P ")) or line == ".P":
            if tag is not None:
                entries.append((tag, " ".join(body)))
            tag, body = None, []
            state = "tag" if line.startswith(".TP") else None
            continue
        if state == "tag":
            tag, state = troff_text(line), "body"
        elif state == "body":
            body.append(troff_text(line))
    return entries


# ---------------------------------------------------------------- the tests


class Links(unittest.TestCase):
    def test_every_relative_link_and_anchor_resolves(self):
        problems = []
        anchor_cache = {}
        for page in markdown_files():
            self.assertTrue(page.is_file(), f"{rel(page)} is missing")
            for number, target in links_of(page):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
                    continue
                where = f"{rel(page)}:{number}: link {target}"
                file_part, _, anchor = target.partition("#")
                linked = (page.parent / file_part).resolve() if file_part else page
                if not linked.exists():
                    problems.append(f"{where}: {rel(linked)} does not exist")
                    continue
                if not anchor:
                    continue
                if linked.suffix != ".md":
                    problems.append(f"{where}: an anchor into {rel(linked)}, which has no headings")
                    continue
                if linked not in anchor_cache:
                    anchor_cache[linked] = anchors_of(linked)
                if anchor not in anchor_cache[linked]:
                    problems.append(f"{where}: no heading of {rel(linked)} has the anchor #{anchor}")
        if problems:
            self.fail("\n" + "\n".join(problems))


class Readme(unittest.TestCase):
    def setUp(self):
        self.lines = (SOURCE / "README.md").read_text(encoding="utf-8").splitlines()

    def test_is_at_most_250_lines(self):
        self.assertLessEqual(len(self.lines), README_MAX_LINES,
                             f"README.md has {len(self.lines)} lines, more than {README_MAX_LINES}: "
                             "move the details to a page of docs/")

    def test_starts_with_its_two_commands(self):
        blocks = code_blocks(self.lines)
        self.assertGreaterEqual(len(blocks), 2, "README.md: fewer than two code blocks")
        first, second = blocks[0].strip(), blocks[1].strip()
        self.assertEqual(len(first.split("\n")), 1,
                         f"README.md: the first code block is not one command:\n{first}")
        for part in ("scripts/install-deps.sh", "cmake -S . -B build", "cmake --build build",
                     "build/fssim --input data/camera.png"):
            self.assertIn(part, first, f"README.md: the first command lacks `{part}`: {first}")
        self.assertEqual(second, "scripts/test.sh",
                         "README.md: the second code block is not `scripts/test.sh`")
        for path in ("scripts/install-deps.sh", "scripts/test.sh", "data/camera.png"):
            self.assertTrue((SOURCE / path).exists(), f"README.md: the commands use {path}, which is missing")
        root_options = {n for o in parse_help(run_help([]))[0] for n in o.long_names}
        for option in long_options_in(first[first.index("build/fssim"):]):
            self.assertIn(option, root_options,
                          f"README.md: the first command uses {option}, which fssim --help does not list")

    def test_ci_runs_the_readme_test_command(self):
        ci = (SOURCE / ".ci" / "run").read_text(encoding="utf-8").splitlines()
        # The command alone on its line, or timed by .ci/run's `stage`.
        runs = [line.strip() for line in ci if re.fullmatch(r"(stage )?scripts/test\.sh", line.strip())]
        self.assertTrue(runs, ".ci/run does not run `scripts/test.sh`, the README's test command")


class Options(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.commands = commands()
        cls.pages = {page: read_lines(page) for page in sorted((SOURCE / "docs").glob("*.md"))}
        cls.man = man_sections(SOURCE / "docs" / "fssim.1")

    def docs_section(self, path):
        """(page, [(number, line)]) of the one docs section whose heading names
        the command; LookupError when there is none or several."""
        found = []
        for page, lines in self.pages.items():
            heads = headings(lines)
            for i, (number, level, text) in enumerate(heads):
                spans = re.findall(r"`([^`]+)`", text)
                if not any(names_command(span.split(), path) for span in spans):
                    continue
                end = len(lines) + 1
                for later_number, later_level, _ in heads[i + 1:]:
                    if later_level <= level:
                        end = later_number
                        break
                body = [(n, lines[n - 1]) for n in range(number + 1, end)]
                found.append((page, number, body))
        name = command_name(path)
        if not found:
            raise LookupError(f"docs/*.md: no heading names `{name}`: its options table has no home")
        if len(found) > 1:
            raise LookupError(f"docs/*.md: several headings name `{name}`: " +
                              ", ".join(f"{rel(p)}:{n}" for p, n, _ in found))
        page, _, body = found[0]
        outside_code = dict(prose_lines([line for _, line in body]))
        return page, [(n, line) for i, (n, line) in enumerate(body, 1) if i in outside_code]

    def man_section(self, path):
        name = command_name(path)
        titles = [t for t in self.man if names_command(t.split(), path)]
        if len(titles) != 1:
            raise LookupError(f"docs/fssim.1: want one .SS section for `{name}`, found {titles}")
        return titles[0], self.man[titles[0]]

    def test_every_command_has_options(self):
        paths = [" ".join(path) for path, _ in self.commands]
        for expected in ("code generate", "code analyze", "code optimize", "sweep", "spectra",
                         "campaign", "campaign merge", "campaign check"):
            self.assertIn(expected, paths, f"fssim --help and its subcommands' helps do not reach `{expected}`")
        self.assertTrue(any(o.default for _, opts in self.commands for o in opts),
                        "no option of any help shows a default: the help's layout changed")

    def test_docs_tables_list_every_option_with_its_default(self):
        problems = []
        for path, options in self.commands:
            documented = [o for o in options if not (path and o.long_names == ["--help"])]
            if not documented:
                continue
            name = command_name(path)
            try:
                page, body = self.docs_section(path)
            except LookupError as error:
                problems.append(str(error))
                continue
            rows, default_column = [], {}
            for table in table_blocks(body):
                header = [c.lower() for c in table[0][1]]
                if not header or header[0] != "option":
                    continue
                for number, cells in table[1:]:
                    rows.append((number, cells, header.index("default") if "default" in header else None))
            where = f"{rel(page)}, section `{name}`"
            if not rows:
                problems.append(f"{where}: no table with an `option` column")
                continue
            listed = set()
            for number, cells, _ in rows:
                listed |= long_options_in(cells[0])
            help_names = {n for o in options for n in o.long_names}
            for extra in sorted(listed - help_names):
                problems.append(f"{where}: lists {extra}, which `{help_command(path)}` does not")
            for option in documented:
                for long_name in option.long_names:
                    pattern = option_pattern(long_name)
                    matching = [(n, c, d) for n, c, d in rows if pattern.search(c[0])]
                    if not matching:
                        problems.append(f"{where}: no row for {long_name}")
                        continue
                    if len(matching) > 1:
                        problems.append(f"{where}: several rows for {long_name} (lines "
                                        + ", ".join(str(n) for n, _, _ in matching) + ")")
                        continue
                    number, cells, column = matching[0]
                    if option.default is None:
                        continue
                    if column is None or column >= len(cells):
                        problems.append(f"{rel(page)}:{number}: {long_name}: no `default` column for the "
                                        f"help's default {option.default!r}")
                    elif not states_default(cells[column], option.default):
                        problems.append(f"{rel(page)}:{number}: {long_name} of `{name}`: the default column "
                                        f"says {cells[column]!r}, `{help_command(path)}` says {option.default!r}")
        if problems:
            self.fail("\n" + "\n".join(problems))

    def test_man_page_lists_every_option_with_its_default(self):
        problems = []
        for path, options in self.commands:
            documented = [o for o in options if not (path and o.long_names == ["--help"])]
            if not documented:
                continue
            name = command_name(path)
            try:
                title, lines = self.man_section(path)
            except LookupError as error:
                problems.append(str(error))
                continue
            where = f"docs/fssim.1, .SS \"{title}\""
            entries = man_entries(lines)
            help_names = {n for o in options for n in o.long_names}
            for tag, _ in entries:
                for extra in sorted(long_options_in(tag) - help_names):
                    problems.append(f"{where}: an entry for {extra}, which `{help_command(path)}` does not list")
            for option in documented:
                for long_name in option.long_names:
                    pattern = option_pattern(long_name)
                    matching = [(t, b) for t, b in entries if pattern.search(t)]
                    if len(matching) != 1:
                        problems.append(f"{where}: {len(matching)} .TP entries for {long_name}, want 1")
                        continue
                    if option.default is None:
                        continue
                    body = matching[0][1]
                    stated = [m.end() for m in re.finditer(r"\bdefault\b:?\s*", body, re.I)]
                    if not any(states_default(body[at:], option.default) for at in stated):
                        problems.append(f"{where}: {long_name}: the entry does not say \"Default: "
                                        f"{option.default}\" (`{help_command(path)}` shows it): {body!r}")
        if problems:
            self.fail("\n" + "\n".join(problems))


if __name__ == "__main__":
    unittest.main(verbosity=2)
