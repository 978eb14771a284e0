# SPDX-License-Identifier: GPL-3.0-or-later
"""Library layering of the C++ sources (docs/architecture.md, "Library
layers"; issue 28 item 1: no objectRegistry lookup by name crosses a library
boundary).

Consistency check of the source text, not a physics test: it reads the
.C/.H files and runs nothing.
- every objectRegistry lookup (lookupObject, lookupObjectRef, findObject,
  foundObject, getObjectPtr) in src/ and applications/ is one of the listed
  OpenFOAM idioms that stay by design (a function object or boundary
  condition reading a field named in its own dictionary, the grainCloud
  registering its own reference); a new one fails here and must either go
  through a typed interface (src/vansCoupling/vansCloud/grainCouplingSource.H)
  or be added to the list with its reason;
- the code (comments stripped) of a lower library names nothing of a higher
  one: grainCloud nothing of vansCoupling/dropletCoupling, vansCoupling
  nothing of dropletCoupling.
"""

import os
import re

import pytest

pytestmark = pytest.mark.fast

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

LOOKUP = re.compile(
    r"\b(lookupObject|lookupObjectRef|findObject|foundObject|getObjectPtr)\s*<[^;{]*?>\s*\(([^)]*)\)"
)

# (file, argument): why it stays
ALLOWED = {
    ("src/grainCloud/grainCloud.C", "registryName"): "grainCloud registers its own reference once",
    (
        "src/freeSurfaceFunctionObjects/freeSurfaceTools.C",
        "grainCloud::registryName",
    ): "a function object gets only the registry (OpenFOAM idiom): granularFront and"
    " grainCentreOfMass find the grains through freeSurfaceTools::grainsOf",
    (
        "src/freeSurfaceFunctionObjects/freeSurfaceTools.C",
        "name",
    ): "function objects read the field named in their dictionary",
    (
        "src/vansCoupling/derivedFvPatchFields/convectiveHeatFlux/"
        "convectiveHeatFluxFvPatchScalarField.C",
        "epsName_",
    ): "boundary condition keyword voidFraction (OpenFOAM idiom)",
}

# names owned by each library that a lower library must not use
HIGHER_NAMES = {
    "src/grainCloud": [
        "vansCloud",
        "overlapMeshAdapter",
        "grainCouplingSource",
        "vapourDroplet",
        "dropletGrain",
        "dropletVolumeSource",
    ],
    "src/vansCoupling": [
        "vapourDroplet",
        "dropletGrain",
        "dropletVolumeSource",
        "dropletHeatSink",
        "granularFront",
        "grainCentreOfMass",
        "waveGauges",
    ],
}


def sources(*dirs):
    for d in dirs:
        for root, _, files in os.walk(os.path.join(ROOT, d)):
            if "lnInclude" in root or os.sep + "Make" in root:
                continue
            for f in files:
                if f.endswith((".C", ".H")):
                    p = os.path.join(root, f)
                    yield os.path.relpath(p, ROOT), open(p, encoding="utf-8").read()


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def test_registry_lookups_are_the_listed_idioms():
    found = set()
    for rel, text in sources(
        "src/grainCloud",
        "src/vansCoupling",
        "src/dropletCoupling",
        "src/freeSurfaceFunctionObjects",
        "applications",
    ):
        for m in LOOKUP.finditer(strip_comments(text)):
            found.add((rel, m.group(2).strip()))
    unexpected = sorted(found - set(ALLOWED))
    assert not unexpected, (
        "objectRegistry lookups by name outside the listed idioms (use a typed "
        f"interface, e.g. grainCouplingSource, or list them with the reason): {unexpected}"
    )


def test_lower_libraries_do_not_name_higher_ones():
    bad = []
    for lib, names in HIGHER_NAMES.items():
        for rel, text in sources(lib):
            code = strip_comments(text)
            bad += [(rel, n) for n in names if re.search(r"\b" + n, code)]
    assert not bad, f"a lower library names a higher one: {bad}"
