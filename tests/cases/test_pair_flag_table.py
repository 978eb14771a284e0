# SPDX-License-Identifier: GPL-3.0-or-later
"""pairFlagTable (src/vansCoupling/vansCloud/pairFlagTable.H), the table of
dry contact pairs the vapour cohesion's predicate reads once per contact row
and sub-step: its answers against a Python dict built from the same pairs
(repeated keys ANDed), for dense ids (the offsets per first id) and sparse
ids (the binary search), with keys absent from the table and the error on
lists of different lengths.  A consistency check of a container against an
independent one; the cohesion physics is tested in test_cohesion.py.  The
header is compiled here with the system's g++ (no OpenFOAM needed): ~3 s."""

import os
import random
import subprocess

import pytest

pytestmark = pytest.mark.fast

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
HEADER_DIR = os.path.join(ROOT, "src", "vansCoupling", "vansCloud")

PROGRAM = r"""
#include "pairFlagTable.H"
#include <cstdio>
#include <iostream>
int main()
{
    std::size_t n, q;
    std::cin >> n;
    std::vector<std::uint64_t> keys(n);
    std::vector<char> flags(n);
    for (std::size_t k = 0; k < n; ++k)
    {
        int f;
        std::cin >> keys[k] >> f;
        flags[k] = char(f);
    }
    Foam::pairFlagTable t;
    t.build(keys, flags);
    std::cout << t.size() << " " << t.count(true) << " " << t.count(false) << "\n";
    std::cin >> q;
    for (std::size_t k = 0; k < q; ++k)
    {
        std::uint64_t key;
        std::cin >> key;
        std::cout << t.find(key) << "\n";
    }
    try
    {
        t.build(keys, std::vector<char>(n + 1));
        std::cout << "no error\n";
    }
    catch (const std::invalid_argument& e)
    {
        std::cout << "error: " << e.what() << "\n";
    }
}
"""


@pytest.fixture(scope="module")
def table_program(tmp_path_factory):
    """The test program compiled against the header."""
    d = tmp_path_factory.mktemp("pairFlagTable")
    src, exe = d / "check.cpp", d / "check"
    src.write_text(PROGRAM)
    subprocess.run(
        [
            "g++",
            "-std=c++17",
            "-O1",
            "-Wall",
            "-Werror",
            "-I",
            HEADER_DIR,
            str(src),
            "-o",
            str(exe),
        ],
        check=True,
    )
    return str(exe)


def key(a, b):
    """pairKey of vapourCohesion.H: first id a, second id or wall code b."""
    return (a << 32) | (b & 0xFFFFFFFF)


@pytest.mark.parametrize("id_span", [2_000, 50_000_000])
def test_pair_flag_table_answers_as_a_dict(table_program, id_span):
    """Every key held answers the AND of its flags, keys never given answer
    -1, and the counts of dry and wet pairs match; 2,000 ids over 3,000
    pairs use the offsets per id, 50,000,000 the sorted search."""
    rng = random.Random(7)
    pairs = []
    for _ in range(3000):
        a = rng.randrange(id_span)
        b = rng.choice([rng.randrange(id_span), -1 - rng.randrange(3)])  # grain or wall
        pairs.append((key(a, b), rng.random() < 0.7))
    pairs += [(k, rng.random() < 0.5) for k, _ in rng.sample(pairs, 500)]  # repeats
    expected = {}
    for k, f in pairs:
        expected[k] = expected.get(k, True) and f
    absent = []
    while len(absent) < 500:
        k = key(rng.randrange(id_span + 10), rng.randrange(id_span))
        if k not in expected:
            absent.append(k)
    queries = list(expected) + absent
    stdin = f"{len(pairs)}\n" + "".join(f"{k} {int(f)}\n" for k, f in pairs)
    stdin += f"{len(queries)}\n" + "".join(f"{k}\n" for k in queries)
    out = subprocess.run(
        [table_program], input=stdin, capture_output=True, text=True, check=True
    ).stdout.split("\n")
    size, dry, wet = map(int, out[0].split())
    assert size == len(expected)
    assert dry == sum(expected.values()) and wet == size - dry
    answers = [int(x) for x in out[1 : 1 + len(queries)]]
    assert answers[: len(expected)] == [int(f) for f in expected.values()]
    assert answers[len(expected) :] == [-1] * len(absent)
    assert out[1 + len(queries)].startswith("error: pairFlagTable::build: keys and flags")
