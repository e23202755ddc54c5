#!/usr/bin/env python3
"""Checks that comments say what the code does and why, not its history (STYLE.md, "Comments
without history"): no issue numbers ("issue 12", "issues 11 and 12", "#12") and no timings
before and after ("0.65 -> 0.67 s") in the comments of the sources, tests, benchmarks,
profiles and scripts. Run by ctest as docs/comments_have_no_history.

Usage: check_comment_history.py SOURCE_DIR

Only comments are read: // and /* */ in C++, JavaScript, CSS and OpenSCAD; # in shell,
Python, TOML and CMake (and Python's docstrings); <!-- --> in HTML. Text in string literals
is code (a G-code line "G1 X10 #5", a colour "#1f77b4") and is not read. A cited upstream
issue is a URL (.../issues/1234), which no pattern takes.
"""
import pathlib
import re
import sys

# The folders and files read, from the repository's root: the modules, the tests and
# benchmarks, the profiles, the scripts, the build files.
ROOTS = ["geometry", "printer", "sim", "host", "app", "tests", "configs", "scripts", "ci",
         "CMakeLists.txt"]

C_LIKE = {".h", ".cpp", ".js", ".css", ".scad"}
HASH = {".sh", ".py", ".toml", ".cmake", ".txt", ".in", ".service", ""}
HTML = {".html"}

PATTERNS = [
    # "issue 12", "Issue #4", "issues 11 and 12", "issue 11's".
    ("an issue number", re.compile(r"\bissues?\s*#?\d+", re.IGNORECASE)),
    # "#12", "(#12)": a number of up to four digits after '#', not a longer one, not hex.
    ("an issue reference", re.compile(r"(?<![\w&#/])#\d{1,4}(?![\w.])")),
    # "0.65 -> 0.67 s", "1.48 s -> 1.41 s", "12 → 9 ms": two figures, the second a time.
    ("a before/after timing", re.compile(
        r"\d[\d.]*\s*(?:s|ms|us|µs|min|h)?\s*(?:->|→)\s*[+-]?\d[\d.]*\s*(?:s|ms|us|µs|min)\b")),
]


def c_like_comments(text):
    """(line number, comment text) for each line of // and /* */ comments, strings skipped."""
    out = []
    i, line, n = 0, 1, len(text)
    while i < n:
        ch = text[i]
        if ch == "\n":
            line += 1
            i += 1
        elif text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end == -1 else end
            out.append((line, text[i + 2:end]))
            i = end
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end == -1 else end
            for k, part in enumerate(text[i + 2:end].split("\n")):
                out.append((line + k, part))
            line += text.count("\n", i, end)
            i = end + 2
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            open_paren = text.find("(", i)
            delimiter = ")" + text[i + 2:open_paren] + '"'
            end = text.find(delimiter, open_paren)
            end = n if end == -1 else end + len(delimiter)
            line += text.count("\n", i, end)
            i = end
        elif ch in "\"'`" and not (ch == "'" and i > 0 and text[i - 1].isalnum()):
            # A string (or a char literal; a digit separator 1'000 is not one): to its closing
            # quote, escapes skipped; a JavaScript template literal may span lines.
            j = i + 1
            while j < n and text[j] != ch and (text[j] != "\n" or ch == "`"):
                j += 2 if text[j] == "\\" else 1
            line += text.count("\n", i, min(j, n))
            i = j + 1
        else:
            i += 1
    return out


def hash_comments(text, python):
    """(line number, comment text) for # comments (and Python's docstrings), strings skipped."""
    out = []
    in_docstring = None
    for number, row in enumerate(text.split("\n"), 1):
        i = 0
        if in_docstring:
            end = row.find(in_docstring)
            out.append((number, row if end == -1 else row[:end]))
            if end == -1:
                continue
            in_docstring, i = None, end + 3
        while i < len(row):
            ch = row[i]
            if python and row.startswith(('"""', "'''"), i):
                quote = row[i:i + 3]
                end = row.find(quote, i + 3)
                if end == -1:
                    out.append((number, row[i + 3:]))
                    in_docstring = quote
                    break
                out.append((number, row[i + 3:end]))
                i = end + 3
            elif ch == "#" and (i == 0 or row[i - 1] not in "$({"):
                out.append((number, row[i + 1:]))
                break
            elif ch in "\"'" and (python or ch == '"' or i == 0 or not row[i - 1].isalnum()):
                j = i + 1
                while j < len(row) and row[j] != ch:
                    j += 2 if row[j] == "\\" and ch == '"' else 1
                i = j + 1
            else:
                i += 1
    return out


def html_comments(text):
    out = []
    for match in re.finditer(r"<!--(.*?)-->", text, re.DOTALL):
        first = text.count("\n", 0, match.start()) + 1
        for k, part in enumerate(match.group(1).split("\n")):
            out.append((first + k, part))
    return out


def comments_of(path):
    text = path.read_text(encoding="utf-8", errors="replace")
    suffix = path.suffix
    if suffix in C_LIKE:
        return c_like_comments(text)
    if suffix in HTML:
        return html_comments(text)
    if suffix in HASH:
        python = suffix == ".py" or text.startswith("#!/usr/bin/env python")
        return hash_comments(text, python)
    return []


def main():
    root = pathlib.Path(sys.argv[1])
    files = []
    for name in ROOTS:
        path = root / name
        if path.is_file():
            files.append(path)
        elif path.is_dir():
            files.extend(p for p in sorted(path.rglob("*")) if p.is_file())
    this_file = pathlib.Path(__file__).resolve()  # its own examples are the patterns' text
    files = [p for p in files if p.resolve() != this_file]
    problems = []
    for path in files:
        for number, comment in comments_of(path):
            for what, pattern in PATTERNS:
                match = pattern.search(comment)
                if match:
                    problems.append(f"  {path.relative_to(root)}:{number}: {what}, "
                                    f"\"{match.group(0)}\": {comment.strip()}")
    if problems:
        print(f"{len(problems)} comments keep history (say what and why; the history is in git):")
        print("\n".join(problems))
        return 1
    print(f"{len(files)} files' comments read, no issue numbers or before/after timings")
    return 0


if __name__ == "__main__":
    sys.exit(main())
