"""stand run --checkpoint: a run killed with SIGKILL resumes from its checkpoint
and gives the same samples as an uninterrupted run (issue 10 item 3)."""
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from stand.scene.model import SceneError
from stand.scene.parse import load_scene
from stand.integrate.simulate import simulate

from _helpers import wait_for

SCENE = "data_samples/scenes/paper001_runup.toml"   # ~3 s of integration, 1e5 revolutions
CHILD = """
import sys
from stand.scene.parse import load_scene
from stand.integrate.simulate import simulate
sc = load_scene(sys.argv[1])
simulate(sc, checkpoint=sys.argv[2], checkpoint_steps=20000)
"""


def test_killed_run_resumes_to_the_same_samples(tmp_path, tmp_path_factory):
    # the first 100 of the sample's 248 s (through the critical speed at 1000 rad/s;
    # 2.7e5 steps = 13 checkpoints instead of 52): enough chunks to be killed between
    scene = tmp_path_factory.mktemp("scene") / "runup.toml"     # not among tmp_path's leftovers
    text = Path(SCENE).read_text()
    assert "duration = 248.0" in text
    scene.write_text(text.replace("duration = 248.0", "duration = 100.0"))
    sc = load_scene(scene)
    # reference: the same chunking without interruption (chunk boundaries restart the
    # step controller's sampling, so a different chunk size differs at ~1e-9 relative)
    ref = simulate(sc, checkpoint=tmp_path / "ref.npz", checkpoint_steps=20000)
    ck = tmp_path / "run.ckpt.npz"
    proc = subprocess.Popen([sys.executable, "-c", CHILD, str(scene), str(ck)], cwd=os.getcwd())
    wait_for(ck.exists, proc, timeout_s=120)     # the first checkpoint is on disk
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    if not ck.exists():
        pytest.skip("the child finished before a checkpoint could be observed")
    leftovers = [p for p in tmp_path.iterdir() if p.name != ck.name]
    tr = simulate(sc, checkpoint=ck, checkpoint_steps=20000)    # resumes
    assert tr.success and not ck.exists()
    np.testing.assert_array_equal(tr.x, ref.x)
    np.testing.assert_array_equal(tr.y, ref.y)
    assert all(p.suffix == ".npz" or ".tmp" in p.name for p in leftovers)


def test_checkpoint_of_another_scene_is_refused(tmp_path):
    sc = load_scene(SCENE)
    ck = tmp_path / "c.npz"
    np.savez(ck, fingerprint=np.array("someone else"))
    with pytest.raises(SceneError, match="another scene"):
        simulate(sc, checkpoint=ck)
    with pytest.raises(SceneError, match="DOP853"):
        simulate(sc, method="Radau", checkpoint=tmp_path / "d.npz")
