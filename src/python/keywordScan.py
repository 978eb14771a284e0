# SPDX-License-Identifier: GPL-3.0-or-later
"""keywordScan: the keyword tables of the C++ sources, for keywordReference.

Every occurrence of the word `checkKeywords` in a C++ file of src/ and
applications/ is classified as a call site, a forwarding call inside a
checkKeywords wrapper, a declaration, a definition, a using-declaration or a
comment; anything else is an ExtractionError (never skipped).  A call site's
table is a brace list of string literals, `wordList()`/`wordList{...}`, or
the name of a wordList defined earlier in the same file (plus its
`.append(...)` calls); entries that are not string literals are kept as
dynamic expressions.  Regex level, with a comment/string-aware scanner.
The page and the checks: keywordReference.py.
"""

import os
import re
from dataclasses import dataclass, field

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DESCRIPTIONS = os.path.join("docs", "keywords.toml")
PAGE = os.path.join("docs", "keywords.md")
SOURCE_DIRS = ("src", "applications")
CXX_EXTENSIONS = (".C", ".H", ".cpp", ".hpp", ".h", ".cxx")
# build trees and OpenFOAM's symlink farms hold copies of the sources
SKIP_DIRS = {"lnInclude", "Make", "build", "platforms", "__pycache__", ".git"}
GENERATOR = "python3 src/python/keywordReference.py"

_CONTROL_WORDS = {
    "if",
    "for",
    "while",
    "switch",
    "return",
    "catch",
    "sizeof",
    "defined",
    "namespace",
    "using",
    "typedef",
    "template",
}


class ExtractionError(RuntimeError):
    """A checkKeywords occurrence or keyword table the extractor cannot read."""


@dataclass
class Site:
    """One checkKeywords call that checks a dictionary.

    key:       "relative/path:function:dictExpression" (function empty at file
               scope), unique over the sources
    path, line: where the call is (repository-relative path, 1-based line)
    keywords:  the accepted keywords read from string literals, in order
    dynamic:   C++ expressions that add keywords at run time
    tables:    where the keywords came from (for messages)
    """

    key: str
    path: str
    line: int
    keywords: list = field(default_factory=list)
    dynamic: list = field(default_factory=list)
    tables: list = field(default_factory=list)


@dataclass
class Occurrence:
    """One occurrence of the word checkKeywords: kind is one of site,
    forward, declaration, definition, using, comment."""

    path: str
    line: int
    kind: str


# ------------------------------------------------------------------ scanning


def _mask(text):
    """Split C++ text into code and comments.

    Returns (code, in_comment): code is text with comments replaced by spaces
    (newlines kept, so offsets and lines are unchanged); in_comment[i] is True
    for a character inside a comment.  String and character literals are
    kept in code (their content is not scanned for comments)."""
    out = list(text)
    in_comment = [False] * len(text)
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            for k in range(i, j):
                out[k] = " "
                in_comment[k] = True
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            for k in range(i, j):
                if text[k] != "\n":
                    out[k] = " "
                in_comment[k] = True
            i = j
        elif c in "\"'":
            i = _skip_string(text, i)
        else:
            i += 1
    return "".join(out), in_comment


def _skip_string(code, j):
    """Index just past the string or character literal starting at code[j]."""
    quote, n = code[j], len(code)
    k = j + 1
    while k < n and code[k] != quote:
        k += 2 if code[k] == "\\" else 1
    return k + 1


def _matching(code, i):
    """Index just past the bracket closing the one at code[i] ((, { or [),
    skipping string literals.  ExtractionError if unbalanced."""
    pairs = {"(": ")", "{": "}", "[": "]"}
    stack = []
    j, n = i, len(code)
    while j < n:
        c = code[j]
        if c in "\"'":
            j = _skip_string(code, j)
            continue
        if c in pairs:
            stack.append(pairs[c])
        elif c in ")}]":
            if not stack or stack.pop() != c:
                raise ExtractionError(f"unbalanced '{c}' at offset {j}")
            if not stack:
                return j + 1
        j += 1
    raise ExtractionError(f"unclosed '{code[i]}' at offset {i}")


def _split_top(code):
    """Split an argument text at its top-level commas (brackets and strings
    respected); returns the stripped parts."""
    parts, depth, start, j, n = [], 0, 0, 0, len(code)
    while j < n:
        c = code[j]
        if c in "\"'":
            j = _skip_string(code, j)
            continue
        if c in "({[":
            depth += 1
        elif c in ")}]":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(code[start:j].strip())
            start = j + 1
        j += 1
    last = code[start:].strip()
    if last or parts:
        parts.append(last)
    return parts


def _line(text, offset):
    return text.count("\n", 0, offset) + 1


def _squash(expr):
    return re.sub(r"\s+", " ", expr).strip()


_DEF_HEAD = re.compile(r"^([A-Za-z_][\w:<>,*& ]*?)\b(~?\w+)\s*\(", re.M)


def _functions(code):
    """Function definitions of a file: list of (name, head, body_start,
    body_end, parameter_names) for every column-0 head `... name(...)`
    followed by a body ({, or : for a constructor's initialiser list)."""
    found = []
    for m in _DEF_HEAD.finditer(code):
        name = m.group(2)
        if name in _CONTROL_WORDS or m.group(1).strip() in _CONTROL_WORDS:
            continue
        open_paren = m.end() - 1
        try:
            close = _matching(code, open_paren)
        except ExtractionError:
            continue
        rest = code[close:]
        after = re.match(r"\s*(?:const\s*)?(?:noexcept\s*)?([{:])", rest)
        if not after:
            continue
        body_open = code.find("{", close)
        if body_open < 0:
            continue
        try:
            body_end = _matching(code, body_open)
        except ExtractionError:
            continue
        params = []
        for p in _split_top(code[open_paren + 1 : close - 1]):
            w = re.findall(r"\w+", p.split("=")[0])
            if w:
                params.append(w[-1])
        found.append((name, m.start(), body_open, body_end, params))
    return found


def _enclosing(functions, offset):
    """The innermost function definition (as _functions gives it) whose body
    holds offset, or None at file scope."""
    best = None
    for f in functions:
        if f[2] < offset < f[3] and (best is None or f[2] > best[2]):
            best = f
    return best


_STRING = re.compile(r'^"((?:[^"\\]|\\.)*)"$')


def _elements(list_text, code, path, type_name):
    """Keywords and dynamic expressions of a brace-list body."""
    keywords, dynamic = [], []
    for e in _split_top(list_text):
        if not e:
            continue
        s = _STRING.match(e)
        if s:
            keywords.append(s.group(1))
            continue
        coeffs = re.fullmatch(r'word\s*\(\s*typeName\s*\+\s*"(\w+)"\s*\)', e)
        if coeffs:
            if not type_name:
                raise ExtractionError(
                    f"{path}: `{_squash(e)}` needs typeName but the file has no"
                    " defineTypeNameAndDebug"
                )
            keywords.append(type_name + coeffs.group(1))
            continue
        dynamic.append(_squash(e))
    return keywords, dynamic


def _literal_table(arg, code, path, type_name):
    """(keywords, dynamic) of a table argument written in place ({...},
    wordList(), wordList{...}, wordList({...})), or None if arg is not one."""
    a = arg.strip()
    m = re.fullmatch(r"(?:Foam::)?wordList\s*(?:\(\s*\)|\{\s*\})", a)
    if m:
        return [], []
    m = (
        re.fullmatch(r"(?:Foam::)?wordList\s*\(\s*(\{.*\})\s*\)", a, re.S)
        or re.fullmatch(r"(?:Foam::)?wordList\s*(\{.*\})", a, re.S)
        or re.fullmatch(r"(\{.*\})", a, re.S)
    )
    if m:
        inner = m.group(1).strip()
        return _elements(inner[1:-1], code, path, type_name)
    return None


def _named_table(name, code, before, path, type_name):
    """(keywords, dynamic, description) of the wordList `name` defined in
    code before offset `before` (the nearest definition), with its later
    `name.append(...)` calls up to `before`.  ExtractionError if undefined."""
    pat = re.compile(r"\bwordList\s+(?:\w+::)*" + re.escape(name) + r"\s*([({])")
    defs = [m for m in pat.finditer(code) if m.start() < before]
    if not defs:
        raise ExtractionError(
            f"{path}: keyword table '{name}' is not a wordList defined earlier in the same file"
        )
    d = defs[-1]
    open_at = d.end() - 1
    close = _matching(code, open_at)
    body = code[open_at:close]
    lit = _literal_table(
        ("wordList" + body) if body.startswith("(") else body, code, path, type_name
    )
    if lit is None:
        raise ExtractionError(f"{path}: cannot read the definition of '{name}'")
    keywords, dynamic = list(lit[0]), list(lit[1])
    app = re.compile(r"\b" + re.escape(name) + r"\s*\.\s*append\s*\(")
    for m in app.finditer(code, close, before):
        a_close = _matching(code, m.end() - 1)
        arg = code[m.end() : a_close - 1]
        sub = _literal_table(arg, code, path, type_name)
        if sub is None:
            dynamic.append(_squash(arg))
        else:
            keywords += sub[0]
            dynamic += sub[1]
    return keywords, dynamic, f"{name} (line {_line(code, d.start())})"


def _source_files(root):
    for top in SOURCE_DIRS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames[:] = sorted(
                d
                for d in dirnames
                if d not in SKIP_DIRS
                and not d.startswith("build")
                and not os.path.islink(os.path.join(dirpath, d))
            )
            for f in sorted(filenames):
                p = os.path.join(dirpath, f)
                if f.endswith(CXX_EXTENSIONS) and not os.path.islink(p):
                    yield p


def scan_sources(root=ROOT):
    """Classify every occurrence of the word checkKeywords in the C++ files
    of src/ and applications/ and read the keyword table of each call site.

    @param root  repository root
    @return (sites, occurrences): the call sites (list of Site, sorted by
            path and line) and every occurrence (list of Occurrence)
    @raises ExtractionError for an occurrence that is none of the known kinds,
            a table that cannot be read, or two sites with the same key
    """
    sites, occurrences = [], []
    for p in _source_files(root):
        with open(p, encoding="utf-8", errors="replace") as f:
            text = f.read()
        if "checkKeywords" not in text:
            continue
        rel = os.path.relpath(p, root)
        code, in_comment = _mask(text)
        functions = _functions(code)
        tn = re.search(r"defineTypeNameAndDebug\s*\(\s*(\w+)", code)
        type_name = tn.group(1) if tn else None
        for m in re.finditer(r"\bcheckKeywords\b", text):
            at, line = m.start(), _line(text, m.start())
            where = f"{rel}:{line}"
            if in_comment[at]:
                occurrences.append(Occurrence(rel, line, "comment"))
                continue
            before = code[:at]
            after = code[m.end() :]
            if re.search(r"\busing\s+(?:\w+::)*$", before):
                occurrences.append(Occurrence(rel, line, "using"))
                continue
            paren = re.match(r"\s*\(", after)
            if not paren:
                raise ExtractionError(f"{where}: checkKeywords not followed by '('")
            open_at = m.end() + paren.end() - 1
            close = _matching(code, open_at)
            if re.search(r"\bvoid\s+(?:\w+::)*$", before):
                nxt = re.match(r"\s*([;{])", code[close:])
                if not nxt:
                    raise ExtractionError(f"{where}: unreadable checkKeywords signature")
                occurrences.append(
                    Occurrence(rel, line, "declaration" if nxt.group(1) == ";" else "definition")
                )
                continue
            qual = re.search(r"((?:\w+::)*)$", before).group(1)
            args = _split_top(code[open_at + 1 : close - 1])
            if len(args) not in (2, 3):
                raise ExtractionError(f"{where}: checkKeywords call with {len(args)} arguments")
            func = _enclosing(functions, at)
            forwarded = set(func[4]) if func and func[0] == "checkKeywords" else set()
            keywords, dynamic, tables = [], [], []
            for arg in args[1:]:
                a = arg.strip()
                lit = _literal_table(a, code, rel, type_name)
                if lit is not None:
                    keywords += lit[0]
                    dynamic += lit[1]
                    tables.append(f"list at line {line}")
                elif re.fullmatch(r"\w+", a) and a in forwarded:
                    tables.append(f"{a} (forwarded parameter)")
                elif re.fullmatch(r"\w+", a):
                    kw, dyn, desc = _named_table(a, code, at, rel, type_name)
                    keywords += kw
                    dynamic += dyn
                    tables.append(desc)
                else:
                    raise ExtractionError(
                        f"{where}: keyword table `{_squash(a)}` is neither a brace"
                        " list nor the name of a wordList of this file"
                    )
            if forwarded and not keywords and not dynamic:
                occurrences.append(Occurrence(rel, line, "forward"))
                continue
            if qual not in (
                "",
                "grainTools::",
                "Foam::grainTools::",
                "freeSurfaceTools::",
                "Foam::freeSurfaceTools::",
                "foamTools::",
                "Foam::foamTools::",
            ):
                raise ExtractionError(f"{where}: unknown checkKeywords {qual}")
            key = f"{rel}:{func[0] if func else ''}:{_squash(args[0])}"
            sites.append(Site(key, rel, line, keywords, dynamic, tables))
            occurrences.append(Occurrence(rel, line, "site"))
    seen = {}
    for s in sites:
        if s.key in seen:
            raise ExtractionError(
                f"{s.path}:{s.line} and line {seen[s.key]}: two call sites with"
                f" the same key {s.key} (same file, function and dictionary"
                " expression); give one of them its own dictionary variable"
            )
        seen[s.key] = s.line
    return sites, occurrences


# ------------------------------------------------------------- descriptions
