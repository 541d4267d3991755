"""``split.NAME`` segmentation parameters: fields of the post-processing (SplitParams) given
with the region-growing ones (``--param split.small_faces=150``)."""

from __future__ import annotations

import numpy as np
import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.segment import segment, split_fields
from planerel.segment.split import SplitParams
from planerel.synth.generator import generate_scene


@pytest.fixture(scope="module")
def stairs():
    # a scene whose labels change when touching regions of one plane are not merged
    return generate_scene("stairs", seed=2, size=(640, 480), subsample=4)


def test_split_fields_separates_and_converts():
    rest, sp = split_fields({"theta": "12", "split.small_faces": "150", "split.merge": "false"})
    assert rest == {"theta": "12"}
    assert sp == SplitParams(small_faces=150, merge=False)
    assert split_fields({"theta": 12}) == ({"theta": 12}, None)
    # usab90: where the names are listed, not "known: <all 30>"
    with pytest.raises(InputError, match="unknown parameter.*smal_faces.*small_faces.*planerel params split"):
        split_fields({"split.smal_faces": 1})
    with pytest.raises(InputError, match="small_faces must be a number"):
        split_fields({"split.small_faces": "many"})
    with pytest.raises(InputError, match="tolerance"):
        split_fields({"split.tolerance": 0.5})  # below its range (>= 1)


def test_segment_routes_split_fields_to_the_post_processing(stairs):
    want = segment(stairs.cloud, split_params=SplitParams(merge=False)).labels
    got = segment(stairs.cloud, **{"split.merge": "false"}).labels
    assert np.array_equal(got, want)
    assert not np.array_equal(got, segment(stairs.cloud).labels)
    with pytest.raises(InputError, match="not both"):
        segment(stairs.cloud, split_params=SplitParams(), **{"split.merge": False})


def test_segment_command_takes_split_fields(stairs, tmp_path, capsys):
    np.save(tmp_path / "st.npy", stairs.cloud.xyz)
    out = tmp_path / "seg"
    assert main(["segment", str(tmp_path / "st.npy"), "-o", str(out), "--formats", "npy",
                 "--param", "split.merge=false"]) == 0
    got = np.load(out / "st.labels.npy")
    assert np.array_equal(got, segment(stairs.cloud, split_params=SplitParams(merge=False)).labels)
    assert main(["segment", str(tmp_path / "st.npy"), "-o", str(tmp_path / "bad"),
                 "--param", "split.merge=perhaps"]) == 2
    assert "merge" in capsys.readouterr().err
    assert not (tmp_path / "bad").exists()  # refused before any work
