"""lorgnette.train: progress callbacks that stop training cleanly, and the GIL released meanwhile."""

import pytest

import lorgnette
from conftest import count_during


def test_progress_returning_false_stops_cleanly(work, dataset):
    seen = []

    def progress(step, seconds, loss):
        seen.append((step, loss))
        return step < 5

    out = work / "stopped.lnerf"
    model = lorgnette.train(str(dataset), str(out), steps=400, batch_log2=12, progress=progress)
    info = model.train_info
    assert info["stopped"] and info["steps"] == 5 and [s for s, _ in seen] == [1, 2, 3, 4, 5]
    assert out.exists()
    again = lorgnette.Model.load(str(out))  # the snapshot saved on stopping is complete
    assert again.metadata["steps"] == 5
    camera = again.orbit(1, size=(24, 16))[0]
    assert again.render(camera).shape == (16, 24, 4)


def test_progress_that_raises_propagates_after_saving(work, dataset):
    def progress(step, seconds, loss):
        if step == 3:
            raise KeyError("stop here")

    out = work / "raised.lnerf"
    with pytest.raises(KeyError, match="stop here"):
        lorgnette.train(str(dataset), str(out), steps=400, batch_log2=12, progress=progress)
    assert lorgnette.Model.load(str(out)).metadata["steps"] == 3


def test_train_releases_the_gil_and_refuses_to_overwrite(work, dataset):
    out = work / "short.lnerf"
    model, counted, seconds = count_during(
        lambda: lorgnette.train(str(dataset), str(out), steps=40, batch_log2=12))
    assert model.train_info["steps"] == 40 and not model.train_info["stopped"]
    assert seconds > 0.1
    assert counted >= max(3, 0.1 * seconds / 0.001), (counted, seconds)  # held GIL: ~0
    with pytest.raises(lorgnette.Error, match="exists"):
        lorgnette.train(str(dataset), str(out), steps=10)
    with pytest.raises(FileNotFoundError):
        lorgnette.train(str(work / "no-dataset"), str(work / "x.lnerf"), steps=10)


def test_a_stopped_training_resumes_from_its_checkpoint(work, dataset):
    out = work / "resumed.lnerf"
    stopped = lorgnette.train(str(dataset), str(out), steps=20, batch_log2=12, deterministic=True,
                              progress=lambda step, seconds, loss: step < 7)
    assert stopped.train_info["stopped"] and stopped.train_info["steps"] == 7
    ckpt = work / "resumed.lnerf.ckpt"
    assert ckpt.exists()
    with pytest.raises(lorgnette.Error, match="unfinished training .* resume=True"):
        lorgnette.train(str(dataset), str(out), steps=20, batch_log2=12, deterministic=True)
    with pytest.raises(lorgnette.Error, match="'steps' \\(20 there, 30 now\\)"):
        lorgnette.train(str(dataset), str(out), steps=30, batch_log2=12, deterministic=True, resume=True)
    model = lorgnette.train(str(dataset), str(out), steps=20, batch_log2=12, deterministic=True, resume=True)
    info = model.train_info
    assert info["steps"] == 20 and not info["stopped"] and len(info["loss_curve"]) == 13
    assert not ckpt.exists()  # the model is complete
    straight = lorgnette.train(str(dataset), str(work / "straight.lnerf"), steps=20, batch_log2=12,
                               deterministic=True)
    assert straight.train_info["loss_curve"][7:] == info["loss_curve"]
