"""Records of ``dptbd.dsp.records``: candidates built on the host, the DSP's input trim."""

import numpy as np
import pytest

from dptbd.dsp.association.config import AssociationError
from dptbd.dsp.records import CANDIDATE_DTYPE, make_candidates


def test_make_candidates_carries_the_path_start():
    raw = np.zeros(2, dtype=[("row", "u2"), ("col", "u2"), ("energy", "u4"), ("direction", "u1")])
    raw["row"], raw["col"], raw["energy"] = [5, 7], [6, 8], [10, 20]
    paths = np.array([[[1, 2], [5, 6]], [[3, 4], [7, 8]]])
    c = make_candidates(raw, paths)
    assert c.dtype == CANDIDATE_DTYPE
    assert c["row0"].tolist() == [1, 3] and c["col0"].tolist() == [2, 4] and c["path"].all()
    c2 = make_candidates(raw)
    assert c2["row0"].tolist() == [5, 7] and not c2["path"].any()
    with pytest.raises(AssociationError, match=(r"^paths must have shape \(2, K, 2\), got \(1, "
                                                r"2, 2\)$")):
        make_candidates(raw, paths[:1])


def test_trim_to_count_is_the_section_6_rule_on_the_list():
    from dptbd.dsp.records import trim_to_count
    from dptbd.model.segmentation import candidates

    rng = np.random.default_rng(3)
    energy = rng.integers(0, 60, (12, 16)).astype(np.uint32)   # many ties
    direction = rng.integers(0, 10, (12, 16)).astype(np.uint8)
    for n in (0, 1, 5, 17, 40):
        ideal = candidates(energy, direction, n)
        superset = candidates(energy, direction, min(3 * n + 4, energy.size - 1))
        np.testing.assert_array_equal(trim_to_count(superset, n), ideal)
        assert len(trim_to_count(ideal, n)) == len(ideal)         # short lists pass through
    with pytest.raises(AssociationError, match=r"^count must be an integer in \[0, inf\), got -1$"):
        trim_to_count(ideal, -1)


def test_records_import_first_in_a_fresh_interpreter():
    # the record formats and the association raise the same error; either may be imported first
    import subprocess
    import sys
    code = ("import dptbd.dsp.records as r, dptbd.dsp.association as a; "
            "assert r.AssociationError is a.AssociationError")
    subprocess.run([sys.executable, "-c", code], check=True)
