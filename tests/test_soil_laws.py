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


#: a law's constants, by the names the Mohr-Coulomb soil keeps them under, and the scene's
#: per-stratum reader: what the plastic state, the collapse study and the bounds once read
LAW_CONSTANTS = re.compile(r"\b(friction_angle|dilation_angle|cohesion_gradient|"
                           r"tensile_strength|sin_phi|sin_psi|point_constants|at_depth)\b|"
                           r"\[\"(cohesion|tension)\"\]")
THROUGH_THE_CONTRACT = ["model/plastic.py", "collapse_study.py",
                        *[f"iterations/{n}.py" for n in ("collapse", "newton", "load_steps",
                                                         "continuation", "excavation")],
                        *[f"bounds/{p.name}" for p in (PACKAGE / "bounds").glob("*.py")]]


def test_the_plastic_state_the_collapse_and_the_bounds_name_no_law_constant():
    """They reach an elastoplastic law's numbers through the point-law contract
    (tankfx.laws.point_law) and the law's strength for the bounds (``limit_strength``)."""
    found = [f"{name}:{k + 1}: {line.strip()}" for name in THROUGH_THE_CONTRACT
             for k, line in enumerate((PACKAGE / name).read_text().splitlines())
             if LAW_CONSTANTS.search(line.split("#")[0])]
    assert not found, "\n".join(found)


#: each law at points' own constants for the test below (a new law adds its line)
POINT_LAW_CONSTANTS = {
    "mohr_coulomb": {"E": 10e6, "cohesion": 10e3, "friction_angle": 20.0},
    "drucker_prager": {"E": 10e6, "cohesion": 10e3, "friction_angle": 20.0},
    "cam_clay": {"lambda_star": 0.1, "kappa_star": 0.02, "M": 1.0, "OCR": 1.5},
}


@pytest.mark.parametrize("word", [w for w, law in SOIL_LAWS.items() if law.at_points])
def test_a_law_at_points_gives_a_point_law_whose_reduction_is_its_own(word):
    """Every law whose state lives at the points gives a PointLaw there; its strength
    divided by 1 is itself, by 2 weaker (the stress level at a state rises), and a masked
    point never yields."""
    import numpy as np

    from tankfx import Scene
    from tankfx.laws.point_law import PointLaw

    soil = Scene.from_dict({"soil": {"model": word, "nu": 0.3, "unit_weight": 18e3,
                                     **POINT_LAW_CONSTANTS[word]},
                            "load": {"pressure": 1e3, "load_radius": 1.0}}).soil
    depth = np.array([0.5, 1.0, 2.0])
    law = soil.law.point_law(soil, depth)
    assert isinstance(law, PointLaw)
    sigma = law.initial_stress() + np.array([0.0, -20e3, 5e3, 0.0])
    once, half = law.reduced(1.0).mobilised(sigma), law.reduced(2.0).mobilised(sigma)
    assert np.allclose(once, law.mobilised(sigma), rtol=1e-12)
    assert np.all(half > 1.2 * once)
    rigid = law.elastic_where(np.array([True, False, False]))
    up = rigid.update(np.full((3, 4), 0.5), np.zeros((3, 4)), rigid.initial_state())
    assert not up.yielding[0] and up.yielding[1:].all()


@pytest.mark.parametrize("word", [w for w, law in SOIL_LAWS.items()
                                  if law.iteration == "secant"])
def test_a_secant_law_satisfies_the_secant_contract(word):
    """Every law the secant iteration solves has what tankfx.laws.secant_law.SecantLaw
    declares (the iteration asks for nothing else)."""
    from tankfx.laws.secant_law import SecantLaw

    assert isinstance(SOIL_LAWS[word], SecantLaw)
    assert not isinstance(SOIL_LAWS["linear"], SecantLaw)
