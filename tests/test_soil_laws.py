"""The soil laws behind one interface: the scene's ``soil.model`` word is looked up in one
registry (tankfx.laws.soil_laws.SOIL_LAWS), and nothing outside the laws branches on it.

Before the registry the word was compared at 29 places and flags derived from it read at 37
more, in 13 modules (docs/development/2026-11-27-soil-laws.md)."""
from __future__ import annotations

import io
import re
import tokenize
from dataclasses import fields
from pathlib import Path

import pytest

from tankfx.iterations.by_law import SOIL_ITERATIONS, soil_iteration
from tankfx.laws.soil_laws import SOIL_LAWS
from tankfx.scene.sections import Layer, Soil

PACKAGE = Path(__file__).resolve().parents[1] / "tankfx"
#: a comparison of a value with a soil model's word ("linear" == x, x in ("hyperbolic", ...))
COMPARISON = re.compile(r"(==|!=|\bin\b|\bis\b)\s*[(\[{]?\s*$|^\s*(==|!=)")


def _compared_words(path: Path) -> list[str]:
    """Where a soil model's word, as a string, is compared with something (strings in
    messages and meanings are not: they are words, not branches)."""
    words = {f'"{w}"' for w in SOIL_LAWS} | {f"'{w}'" for w in SOIL_LAWS}
    tokens = list(tokenize.generate_tokens(io.StringIO(path.read_text()).readline))
    out = []
    for i, tok in enumerate(tokens):
        if tok.type != tokenize.STRING or tok.string not in words:
            continue
        before = " ".join(t.string for t in tokens[max(i - 3, 0):i]
                         if t.type in (tokenize.OP, tokenize.NAME))
        after = tokens[i + 1].string if i + 1 < len(tokens) else ""
        if COMPARISON.search(before) or after in ("==", "!="):
            out.append(f"{path.name}:{tok.start[0]}: {tok.line.strip()}")
    return out


def _outside_the_laws(find) -> list[str]:
    """What ``find`` finds in every module of tankfx outside ``laws/``."""
    return [f"{path.parent.name}/{hit}" for path in sorted(PACKAGE.rglob("*.py"))
            if "laws" not in path.relative_to(PACKAGE).parts for hit in find(path)]


def test_nothing_outside_the_laws_compares_the_soil_model():
    found = _outside_the_laws(_compared_words)
    assert not found, "\n".join(found)


def test_the_check_finds_a_comparison(tmp_path):
    """(The check above sees what it looks for.)"""
    code = tmp_path / "x.py"
    code.write_text('if soil.model == "duncan_chang":\n    pass\nif m in ("linear", "x"):\n'
                    '    pass\nprint("model = \\"hyperbolic\\"")\n')
    hits = _compared_words(code)
    assert len(hits) == 2 and ":1:" in hits[0] and ":3:" in hits[1]


#: names of flags once derived from the soil model and branched on (Soil.nonlinear,
#: self.duncan_chang, dc, linear_soil, SoilBlock.kondner, the kondner module as hyperbolic)
FLAGS = {"nonlinear", "duncan_chang", "dc", "linear_soil", "kondner", "hyperbolic"}


def _flag_reads(path: Path) -> list[str]:
    """Where such a flag is read: a name, not in a string, comment, import or definition,
    and not an assignment's target."""
    tokens = list(tokenize.generate_tokens(io.StringIO(path.read_text()).readline))
    out = []
    for i, tok in enumerate(tokens):
        if tok.type != tokenize.NAME or tok.string not in FLAGS:
            continue
        if tok.line.lstrip().startswith(("import ", "from ", "def ", "class ")):
            continue
        after = tokens[i + 1].string if i + 1 < len(tokens) else ""
        if after == "=" or (i and tokens[i - 1].string in ("def", "class", "as")):
            continue
        out.append(f"{path.name}:{tok.start[0]}: {tok.line.strip()}")
    return out


def test_nothing_outside_the_laws_reads_a_flag_of_the_soil_model():
    """(43 reads on main 7827b1c, 12 of them in iterations/secant.py.)"""
    found = _outside_the_laws(_flag_reads)
    assert not found, "\n".join(found)


def test_the_check_finds_a_flag_read(tmp_path):
    code = tmp_path / "x.py"
    code.write_text('nonlinear = soil.nonlinear\nif nonlinear:\n    pass\n'
                    'from x import kondner\n# dc\nprint("dc")\n')
    hits = _flag_reads(code)
    assert len(hits) == 2 and ":1:" in hits[0] and ":2:" in hits[1]


@pytest.mark.parametrize("word", list(SOIL_LAWS))
def test_every_law_is_a_scene_word_with_keys_the_scene_declares(word):
    law = SOIL_LAWS[word]
    assert law.word == word
    assert word in Soil.__dataclass_fields__["model"].metadata["key"].choices
    soil_fields = {f.name for f in fields(Soil)}
    layer_fields = {f.name for f in fields(Layer)}
    assert set(law.keys) <= soil_fields and set(law.iteration_keys) <= soil_fields
    assert set(law.layer_keys) <= layer_fields and set(law.E_keys) <= soil_fields
    # its iteration exists, and says what it does
    if law.iteration is None:
        assert soil_iteration(law) is None and not law.state_fields
    else:
        assert soil_iteration(law) is SOIL_ITERATIONS[law.iteration]
        assert law.max_iterations and law.iteration_keys
