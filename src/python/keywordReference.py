# SPDX-License-Identifier: GPL-3.0-or-later
"""keywordReference: the keyword reference docs/keywords.md, generated.

Every dictionary of the project is keyword-checked in C++ by
grainTools::checkKeywords(dict, allowed[, generic]) (or its function-object
wrapper freeSurfaceTools::checkKeywords(dict, own)): an unknown keyword is a
FatalIOError.  This module reads those keyword tables out of the C++ sources
(src/, applications/) and merges them with the hand-kept descriptions of
docs/keywords.toml (units, default, allowed values, meaning, and which file and
sub-dictionary each table checks) to write docs/keywords.md.  The page and
the checks therefore come from the same tables; tests/cases/test_keywordReference.py
fails when they drift.

Regenerate the page (after changing a keyword table or docs/keywords.toml):

    python3 src/python/keywordReference.py            # writes docs/keywords.md
    python3 src/python/keywordReference.py --check    # exit 1 if out of date

C++ extraction (regex level, with a comment/string-aware scanner): every
occurrence of the word `checkKeywords` in a C++ file is classified as a call
site, a forwarding call inside a checkKeywords wrapper, a declaration, a
definition, a using-declaration or a comment; anything else is an
ExtractionError (never skipped).  A call site's table is a brace list of
string literals, `wordList()`/`wordList{...}`, or the name of a wordList
defined earlier in the same file (plus its `.append(...)` calls).  Entries
that are not string literals (e.g. `allowed.append(phases)`) are kept as
*dynamic* expressions, which docs/keywords.toml documents by hand with a
placeholder keyword (`dynamic = { "phases" = "<phase>" }`).
`word(typeName + "Coeffs")` is resolved from the file's
defineTypeNameAndDebug.

Description file, docs/keywords.toml: a list of [[dictionary]] tables, each
    file         = where the user writes it ("constant/grainProperties")
    path         = sub-dictionary inside it ("" top level, "materials.<name>")
    applications = the solvers/utilities that read it
    sites        = call sites "relative/path.C:function:dictExpression"
                   (printed by `--sites`); [] for a dictionary read but not
                   keyword-checked, which then needs `unchecked = "<why>"`
    about        = one paragraph (optional)
    dynamic      = { "<C++ expression>" = "<placeholder keyword>" } (optional)
    [dictionary.keywords]
    name = { meaning = "...", default = "...", unit = "...", allowed = "..." }
(meaning and default required; "required" as default for mandatory keywords).
"""

import argparse
import os
import re
import sys

try:
    import tomllib  # Python >= 3.11 (Debian 12)
except ImportError:  # pragma: no cover
    import tomli as tomllib
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


class DescriptionError(RuntimeError):
    """docs/keywords.toml is malformed or disagrees with the C++ tables."""


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

_ENTRY_FIELDS = {"meaning", "default", "unit", "allowed"}
_DICT_FIELDS = {
    "file",
    "path",
    "variant",
    "applications",
    "sites",
    "about",
    "dynamic",
    "unchecked",
    "keywords",
}


def load_descriptions(root=ROOT):
    """Read docs/keywords.toml.

    @param root  repository root
    @return the list of dictionary tables (dicts with the fields described in
            the module docstring; `keywords` keeps the file's order)
    @raises DescriptionError on a TOML syntax error, an unknown or missing field
    """
    p = os.path.join(root, DESCRIPTIONS)
    try:
        with open(p, "rb") as f:
            data = tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise DescriptionError(f"{DESCRIPTIONS}: {e}") from e
    dicts = data.get("dictionary")
    if not isinstance(dicts, list) or set(data) != {"dictionary"}:
        raise DescriptionError(f"{DESCRIPTIONS}: expected only [[dictionary]] tables")
    for d in dicts:
        name = f"{d.get('file')} {d.get('path', '')}".strip()
        unknown = set(d) - _DICT_FIELDS
        if unknown:
            raise DescriptionError(f"{DESCRIPTIONS}: [{name}] unknown fields {sorted(unknown)}")
        for req in ("file", "applications", "sites"):
            if req not in d:
                raise DescriptionError(f"{DESCRIPTIONS}: [{name}] has no '{req}'")
        if not d["sites"] and not d.get("unchecked"):
            raise DescriptionError(
                f'{DESCRIPTIONS}: [{name}] has no sites: say why in unchecked = "..."'
            )
        d.setdefault("path", "")
        d.setdefault("keywords", {})
        d.setdefault("dynamic", {})
        for k, e in d["keywords"].items():
            if not isinstance(e, dict):
                raise DescriptionError(f"{DESCRIPTIONS}: [{name}] {k} must be a table")
            bad = set(e) - _ENTRY_FIELDS
            if bad:
                raise DescriptionError(
                    f"{DESCRIPTIONS}: [{name}] {k}: unknown fields {sorted(bad)}"
                )
            for req in ("meaning", "default"):
                if not str(e.get(req, "")).strip():
                    raise DescriptionError(f"{DESCRIPTIONS}: [{name}] {k} has no {req}")
    return dicts


def check(sites, dicts, root=ROOT):
    """Compare the C++ keyword tables with the descriptions.

    @param sites  call sites of scan_sources
    @param dicts  dictionary tables of load_descriptions
    @param root   repository root (for the literal search of unchecked tables)
    @return a list of problems (strings, each with its fix); empty if the two agree.
            Reported: a call site no [[dictionary]] lists; a site listed twice or
            listed but absent from the sources (stale); a checked keyword or
            dynamic expression with no description; a described keyword no
            check accepts (stale); a keyword of an unchecked dictionary that
            appears as a string literal in no C++ source.
    """
    problems = []
    fix = f"fix {DESCRIPTIONS}, then run `{GENERATOR}`"
    by_key = {s.key: s for s in sites}
    owner = {}
    for d in dicts:
        name = f"{d['file']} {d['path']}".strip()
        for key in d["sites"]:
            if key in owner:
                problems.append(f"site {key} is listed by both [{owner[key]}] and [{name}]; {fix}")
            owner[key] = name
            if key not in by_key:
                problems.append(
                    f"[{name}] lists site {key}, which no checkKeywords call has"
                    f" (stale: renamed or removed?); sites now: `{GENERATOR} --sites`; {fix}"
                )
    for s in sites:
        if s.key not in owner:
            problems.append(
                f"{s.path}:{s.line}: checkKeywords site {s.key} (keywords"
                f" {', '.join(s.keywords) or 'none'}) is in no [[dictionary]] of"
                f' {DESCRIPTIONS}; add one with sites = ["{s.key}"]; {fix}'
            )
    for d in dicts:
        name = f"{d['file']} {d['path']}".strip()
        documented = d["keywords"]
        if not d["sites"]:
            literals = _all_literals(root)
            for k in documented:
                if not k.startswith("<") and k not in literals:
                    problems.append(
                        f"[{name}] (unchecked) documents '{k}', which appears as a"
                        f" string literal in no C++ source (stale); {fix}"
                    )
            continue
        accepted = []
        for key in d["sites"]:
            s = by_key.get(key)
            if s is None:
                continue
            for k in s.keywords:
                if k not in accepted:
                    accepted.append(k)
                if k not in documented:
                    problems.append(
                        f"{s.path}:{s.line}: keyword '{k}' checked for {name} has no"
                        f" entry in {DESCRIPTIONS} (and so none on {PAGE}); {fix}"
                    )
            for expr in s.dynamic:
                ph = d["dynamic"].get(expr)
                if ph is None:
                    problems.append(
                        f"{s.path}:{s.line}: the keyword table of {name} grows at run"
                        f" time by `{expr}`; document it by hand: dynamic ="
                        f' {{ "{expr}" = "<placeholder>" }} and a keyword'
                        f' "<placeholder>"; {fix}'
                    )
                elif ph not in documented:
                    problems.append(
                        f"[{name}] maps `{expr}` to '{ph}', which has no keyword entry; {fix}"
                    )
                elif ph not in accepted:
                    accepted.append(ph)
        for expr in d["dynamic"]:
            if not any(expr in by_key[k].dynamic for k in d["sites"] if k in by_key):
                problems.append(
                    f"[{name}] dynamic `{expr}`: no site of it has this"
                    f" expression any more (stale); {fix}"
                )
        for k in documented:
            if k not in accepted:
                problems.append(
                    f"[{name}] documents '{k}', which no keyword check of"
                    f" {', '.join(d['sites'])} accepts (stale); {fix}"
                )
    return problems


_LITERALS = {}


def _all_literals(root):
    """Every string literal of the C++ sources of src/ and applications/."""
    if root not in _LITERALS:
        lits = set()
        for p in _source_files(root):
            with open(p, encoding="utf-8", errors="replace") as f:
                lits.update(re.findall(r'"((?:[^"\\\n]|\\.)*)"', f.read()))
        _LITERALS[root] = lits
    return _LITERALS[root]


# ----------------------------------------------------------------- the page


def _cell(s):
    """A table cell: pipes escaped, `<word>` kept visible (not an HTML tag)."""
    s = " ".join(str(s).split()).replace("|", "\\|")
    s = re.sub(r"<(?=[A-Za-z/!])", "&lt;", s)
    return s if s else "-"


def _anchor(title):
    a = re.sub(r"[^\w\- ]", "", title.lower()).strip().replace(" ", "-")
    return a


def render(sites, dicts):
    """The Markdown text of docs/keywords.md.

    @param sites  call sites of scan_sources (for the source links)
    @param dicts  dictionary tables of load_descriptions, in page order
    @return the page (str, ending in a newline)
    """
    by_key = {s.key: s for s in sites}
    files = []
    for d in dicts:
        if d["file"] not in files:
            files.append(d["file"])
    n_kw = sum(len(d["keywords"]) for d in dicts)
    out = [
        "<!-- Generated by src/python/keywordReference.py from the C++ keyword",
        "     tables and docs/keywords.toml. Do not edit: edit docs/keywords.toml",
        f"     (or the C++ table) and run `{GENERATOR}`. -->",
        "",
        "# Keyword reference",
        "",
        "Every keyword of every dictionary that nscdFoam's solvers (grainFoam,",
        "vansFoam, vansInterFoam), utilities (grainDeposit, grainVoidFraction,",
        "nusseltTable), fvOptions, boundary conditions and function objects read,",
        "with its unit, default and allowed values.  The keyword lists are read out",
        "of the C++ keyword checks (`grainTools::checkKeywords`: an unknown keyword",
        "is a FatalIOError naming the file, the line and the allowed keywords), so",
        "this page cannot list a keyword the code refuses or miss one it accepts;",
        "`tests/cases/test_keywordReference.py` fails when the two drift.",
        "Regenerate with",
        "",
        "```sh",
        GENERATOR,
        "```",
        "",
        f"{len(dicts)} dictionaries, {n_kw} keywords, from {len(sites)} keyword checks.",
        "Default `required`: the keyword must be given.  Unit `-`: dimensionless or",
        "a word/switch.  `<name>`: an entry whose keyword you choose (a material, a",
        "patch, a phase).  Switches accept yes/no, on/off, true/false.",
        "",
        "## Contents",
        "",
    ]
    for fname in files:
        out.append(f"- [`{fname}`](#{_anchor(fname)})")
        for d in dicts:
            if d["file"] == fname:
                t = _title(d)
                out.append(f"  - [{t}](#{_anchor(t)})")
    for fname in files:
        out += ["", f"## `{fname}`"]
        for d in dicts:
            if d["file"] != fname:
                continue
            out += ["", f"### {_title(d)}", ""]
            out.append("Read by: " + ", ".join(f"`{a}`" for a in d["applications"]) + ".")
            if d["sites"]:
                # file and function, no line numbers: the page must not
                # change when unrelated code above a check moves
                refs = []
                for key in d["sites"]:
                    s = by_key.get(key)
                    if s is not None:
                        func = s.key.split(":")[1]
                        ref = f"[`{s.path}`](../{s.path})" + (f" (`{func}`)" if func else "")
                        if ref not in refs:
                            refs.append(ref)
                out.append("Keywords checked in " + ", ".join(refs) + ".")
            else:
                out.append(f"**Not keyword-checked** ({d['unchecked'].strip()}).")
            if d.get("about"):
                out += ["", " ".join(d["about"].split())]
            out.append("")
            if not d["keywords"]:
                out.append("No keywords (the dictionary may be absent or empty).")
                continue
            out.append("| keyword | unit | default | allowed | meaning |")
            out.append("|---|---|---|---|---|")
            for k, e in d["keywords"].items():
                out.append(
                    f"| `{k}` | {_cell(e.get('unit', '-'))} | "
                    f"{_cell(e['default'])} | {_cell(e.get('allowed', '-'))} | "
                    f"{_cell(' '.join(e['meaning'].split()))} |"
                )
    return "\n".join(out) + "\n"


def _title(d):
    """Heading of a dictionary: file and sub-dictionary as code (so that
    `<name>` shows), and the variant."""
    t = f"`{d['file']}` `{d['path']}`" if d["path"] else f"`{d['file']}` (top level)"
    return t + (f", {d['variant']}" if d.get("variant") else "")


def generate(root=ROOT):
    """Extract, check and render.

    @param root  repository root
    @return the page text
    @raises ExtractionError, DescriptionError (with every problem listed) when
            the C++ tables and docs/keywords.toml disagree
    """
    sites, _ = scan_sources(root)
    dicts = load_descriptions(root)
    problems = check(sites, dicts, root)
    if problems:
        raise DescriptionError("\n".join(problems))
    return render(sites, dicts)


def main(argv=None):
    """Command line: write docs/keywords.md (default), --check (exit 1 if the
    page is out of date), --sites (print the call sites and their keywords)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument(
        "--check",
        action="store_true",
        help="do not write; exit 1 if docs/keywords.md is out of date",
    )
    ap.add_argument(
        "--sites", action="store_true", help="print every checkKeywords site with its keywords"
    )
    ap.add_argument("--root", default=ROOT)
    a = ap.parse_args(argv)
    if a.sites:
        sites, occ = scan_sources(a.root)
        for s in sites:
            print(f"{s.key}  ({s.path}:{s.line})")
            print("    keywords: " + " ".join(s.keywords))
            if s.dynamic:
                print("    dynamic:  " + " | ".join(s.dynamic))
        kinds = {}
        for o in occ:
            kinds[o.kind] = kinds.get(o.kind, 0) + 1
        print(f"{len(occ)} occurrences of checkKeywords: {kinds}")
        return 0
    try:
        page = generate(a.root)
    except (ExtractionError, DescriptionError) as e:
        print(f"keywordReference: {e}", file=sys.stderr)
        return 1
    p = os.path.join(a.root, PAGE)
    old = open(p).read() if os.path.exists(p) else None
    if a.check:
        if old != page:
            print(f"{PAGE} is out of date: run `{GENERATOR}`", file=sys.stderr)
            return 1
        return 0
    if old != page:
        with open(p, "w") as f:
            f.write(page)
        print(f"wrote {PAGE}")
    else:
        print(f"{PAGE} up to date")
    return 0


if __name__ == "__main__":
    sys.exit(main())
