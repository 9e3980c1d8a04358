"""rolling_friction jiang, test (h): bad input stops LIGGGHTS with an ERROR
line that names the offending keyword or property, in `pair_style gran`
and in `fix wall/gran` -- not a crash, not a hang, not a silent run.

Each deck is two discs pressed 1e-4 m into each other (pair) or one disc
pressed 1e-4 m into the plane z = 0 (wall), so that the contact exists from
the first step and the run-time check on l_c is reached; 2 steps each.
The same decks with good input run (positive controls), so every refusal
below is caused by the one input that differs.

In `fix wall/gran` the model keywords go after the wall arguments
(`... rolling_friction jiang primitive type 1 zplane 0.0 rollingDamping on`):
fix_wall_gran.cpp hands the model settings only what follows the wall
definition, and a keyword placed before `primitive` is refused with
"Unknown argument or wrong keyword order: 'primitive'" (stock behaviour;
checked in test_wall_keywords_before_wall_arguments_are_refused).

run_deck is conftest.run_liggghts with a timeout (a hang fails the test)
and batch=True: the output goes to files without stdbuf, as in a cluster
job, so every message checked here is one that reaches such a file.
"""


import pytest

from analysis.testing import LiggghtsError
from conftest import has_mpirun, run_liggghts
from analysis.common.deck_blocks import granular_setup, hooke_materials, per_pair

RADIUS = 0.005
OVERLAP = 1.0e-4
CONTACT_LENGTH = 1.0e-3
JIANG = "model hooke/stiffness tangential history rolling_friction jiang"
TIMEOUT = 120           # a hang shows up as TimeoutExpired, i.e. a failure


def run_deck(deck, workdir, nprocs=1):
    # batch: output to files, no stdbuf, as a cluster job (tests/test_batch_errors.py)
    return run_liggghts(deck, workdir, nprocs=nprocs, timeout=TIMEOUT, batch=True)


def deck(where, settings="", properties=per_pair("rollingContactLength", CONTACT_LENGTH),
         diameters=(2 * RADIUS, 2 * RADIUS), ntypes=1, steps=2):
    """`where` = "pair": the jiang model in pair_style gran, two discs in
    contact; "wall": plain pair_style, the jiang model in fix wall/gran, one
    disc on the plane z = 0. `settings` are the model keywords."""
    if where == "pair":
        interaction = f"pair_style gran {JIANG} {settings}\npair_coeff * *"
        distance = 0.5 * (diameters[0] + diameters[1]) - OVERLAP
        atoms = (f"create_atoms 1 single 0 0 0 units box\n"
                 f"create_atoms {ntypes} single {distance!r} 0 0 units box\n"
                 f"set atom 1 diameter {diameters[0]!r} density 2500\n"
                 f"set atom 2 diameter {diameters[1]!r} density 2500")
    else:
        interaction = (f"pair_style gran model hooke/stiffness tangential history\n"
                       f"pair_coeff * *\n"
                       f"fix floor all wall/gran {JIANG} primitive type 1 zplane 0.0 {settings}")
        atoms = (f"create_atoms 1 single 0 0 {0.5 * diameters[0] - OVERLAP!r} units box\n"
                 f"set atom 1 diameter {diameters[0]!r} density 2500")
    return f"""
{granular_setup()}
region box block -0.03 0.03 -0.03 0.03 -0.03 0.03 units box
create_box {ntypes} box
neighbor 0.001 bin
neigh_modify delay 0
{hooke_materials(1.0e5, 4.0e4, mu=0.5, ntypes=ntypes)}
{properties}
{interaction}
timestep 1e-5
{atoms}
set atom 1 omegaz 5.0
fix integ all nve/sphere
run {steps}
"""


def refused(workdir, deck_text, **kwargs):
    with pytest.raises(LiggghtsError) as caught:
        run_deck(deck_text, workdir, **kwargs)
    return caught.value.message


WHERE = ["pair", "wall"]


# ------------------------------------------------------ positive controls

@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
@pytest.mark.parametrize("settings, properties", [
    ("", per_pair("rollingContactLength", CONTACT_LENGTH)),
    # l_c equal to the diameter is allowed ("not larger than")
    ("", per_pair("rollingContactLength", 2 * RADIUS)),
    ("contactLengthFromOverlap on", ""),
    ("contactLengthFromDepth on", ""),
    ("contactLengthFromOverlap off rollingStiffnessFactor 0.5 rollingFrictionFactor 2",
     per_pair("rollingContactLength", CONTACT_LENGTH)),
    ("rollingDamping on", per_pair("rollingContactLength", CONTACT_LENGTH)
     + per_pair("coefficientRollingViscousDamping", 0.3)),
    ("rollingDamping off", per_pair("rollingContactLength", CONTACT_LENGTH)),
], ids=["fixed", "lc_equals_diameter", "overlap", "depth", "factors", "damping_on", "damping_off"])
def test_good_input_runs(tmp_path, where, settings, properties):
    output = run_deck(deck(where, settings, properties), tmp_path)
    assert "Loop time" in output
    assert "ERROR" not in output


# ---------------------------------------------------- rollingContactLength

@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
def test_missing_contact_length(tmp_path, where):
    # fixed mode (the default) needs the property; LIGGGHTS' registry names it
    message = refused(tmp_path, deck(where, properties=""))
    assert "rollingContactLength" in message
    assert "rolling_friction jiang" in message


@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
def test_contact_length_negative(tmp_path, where):
    # 0 is allowed (no rolling resistance for that pair; test_jiang_statics_rolling)
    message = refused(tmp_path, deck(where, properties=per_pair("rollingContactLength", -1.0e-3)))
    assert "rollingContactLength must be >= 0" in message
    assert "types 1 1" in message


@pytest.mark.engine
def test_contact_length_negative_names_the_type_pair(tmp_path):
    # two types, only the 1-2 entries are negative: the check covers every pair
    properties = "fix m_lc all property/global rollingContactLength peratomtypepair 2 1e-3 -1e-3 -1e-3 1e-3\n"
    message = refused(tmp_path, deck("pair", properties=properties, ntypes=2))
    assert "rollingContactLength must be >= 0" in message
    assert "types 1 2" in message


# l_c larger than a grain diameter is found at the contact, on the rank
# that owns it, so it is an error->one (print, then MPI_Abort). Stock
# Error::one does not flush stdout before the abort and writes nothing to
# the log, so the model writes the message to stderr and the log first: it
# must reach a serial batch run's captured output and a run under
# mpirun -np 2.

LARGE = 2 * RADIUS * 1.1


@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
def test_contact_length_larger_than_diameter(tmp_path, where):
    message = refused(tmp_path, deck(where, properties=per_pair("rollingContactLength", LARGE)))
    assert "rollingContactLength" in message
    assert "larger than the diameter 0.01" in message


@pytest.mark.engine
def test_contact_length_larger_than_smaller_diameter(tmp_path):
    # polydisperse pair d = 0.01 and 0.02: l_c = 0.015 fits the larger grain
    # but not the smaller one, which is what counts
    text = deck("pair", properties=per_pair("rollingContactLength", 0.015),
                diameters=(0.01, 0.02))
    message = refused(tmp_path, text)
    assert "rollingContactLength 0.015" in message
    assert "larger than the diameter 0.01" in message


@pytest.mark.engine
@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_contact_length_larger_than_diameter_two_ranks(tmp_path):
    # the two grains sit on different ranks; error->one on one rank must
    # take the other down (no hang: run_deck has a timeout)
    message = refused(tmp_path, deck("pair", properties=per_pair("rollingContactLength", LARGE)),
                      nprocs=2)
    assert "rollingContactLength" in message
    assert "larger than the diameter" in message


@pytest.mark.engine
def test_contact_length_too_large_message_in_batch_output(tmp_path):
    with pytest.raises(LiggghtsError) as caught:
        run_deck(deck("pair", properties=per_pair("rollingContactLength", LARGE)), tmp_path)
    # it stops (no hang), and the reason is both in the captured output and
    # in the log file, although error->one aborts without flushing either
    log = (tmp_path / "log.liggghts").read_text(errors="replace")
    assert "rollingContactLength" in caught.value.message
    assert "rollingContactLength" in log


# ------------------------------------------------------ the two factors

@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
@pytest.mark.parametrize("keyword", ["rollingStiffnessFactor", "rollingFrictionFactor"])
@pytest.mark.parametrize("value", ["0", "-1", "abc"])
def test_factor_not_positive(tmp_path, where, keyword, value):
    # "abc" goes through atof to 0 and is refused as such
    message = refused(tmp_path, deck(where, f"{keyword} {value}"))
    assert f"rolling_friction jiang: {keyword} must be > 0" in message


# ------------------------------------------------------ on/off keywords

@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
@pytest.mark.parametrize("keyword", ["contactLengthFromOverlap", "contactLengthFromDepth", "rollingDamping"])
def test_on_off_unknown_value(tmp_path, where, keyword):
    message = refused(tmp_path, deck(where, f"{keyword} maybe"))
    assert f"while parsing '{keyword}' argument" in message
    assert "'maybe'" in message


@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
def test_overlap_and_depth_exclude_each_other(tmp_path, where):
    message = refused(tmp_path, deck(where, "contactLengthFromOverlap on contactLengthFromDepth on",
                                     properties=""))
    assert "contactLengthFromOverlap and contactLengthFromDepth exclude each other" in message


@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
def test_unknown_keyword(tmp_path, where):
    message = refused(tmp_path, deck(where, "rollingStiffness 2"))
    assert "Unknown argument" in message
    assert "'rollingStiffness'" in message


@pytest.mark.engine
def test_wall_keywords_before_wall_arguments_are_refused(tmp_path):
    text = deck("wall").replace(f"{JIANG} primitive",
                                f"{JIANG} contactLengthFromOverlap on primitive")
    message = refused(tmp_path, text)
    assert "wrong keyword order: 'primitive'" in message


# A keyword with no value at the very end of the command: LIGGGHTS'
# settings.h reads the value from one past the end of the argument list.
# pair_style happens to find leftover text there (undefined behaviour, it
# shows up as e.g. "unknown option ...: 'istory'"); fix wall/gran crashes:
# SIGSEGV for the factors (atof(NULL)), SIGABRT for on/off keywords
# (std::string(NULL)). Stock LIGGGHTS, documented here because it is what
# a user of these keywords meets.

@pytest.mark.xfail(strict=True, reason="stock settings.h: value read past the end of the "
                   "arguments; fix wall/gran dies with SIGSEGV/SIGABRT, no ERROR line")
@pytest.mark.parametrize("keyword", ["rollingStiffnessFactor", "contactLengthFromOverlap"])
def test_wall_keyword_without_value(tmp_path, keyword):
    message = refused(tmp_path, deck("wall", keyword))
    assert keyword in message


# --------------------------------------------------- rollingDamping on

@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
def test_damping_without_coefficient(tmp_path, where):
    message = refused(tmp_path, deck(where, "rollingDamping on"))
    assert "coefficientRollingViscousDamping" in message
    assert "rolling_friction jiang" in message


@pytest.mark.engine
@pytest.mark.parametrize("where", WHERE)
def test_overlap_mode_needs_no_contact_length(tmp_path, where):
    # the other side of test_missing_contact_length: with l_c from the
    # overlap the property is not asked for, and an unused one is harmless
    run_deck(deck(where, "contactLengthFromOverlap on", properties=""), tmp_path / "without")
    run_deck(deck(where, "contactLengthFromOverlap on"), tmp_path / "with")
