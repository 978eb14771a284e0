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

from keywordScan import (  # noqa: F401  (kr.X in the tests)
    CXX_EXTENSIONS,
    DESCRIPTIONS,
    GENERATOR,
    PAGE,
    ROOT,
    SKIP_DIRS,
    SOURCE_DIRS,
    ExtractionError,
    Site,
    _source_files,
    scan_sources,
)


class DescriptionError(RuntimeError):
    """docs/keywords.toml is malformed or disagrees with the C++ tables."""


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
