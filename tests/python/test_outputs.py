"""Issue 31 item 3: outputs that survive (one writer per folder, whole files, Ctrl-C keeps finished blocks)."""
import json

import pytest

from drillpy.cli import main
from drillpy.outputs import LOCK_NAME, folder_lock, replacing, write_text

RIG = ["--preset", "thesis-rig", "--duration", "2", "--transient", "1", "--no-progress"]


def test_an_empty_out_is_an_error(capsys):
    assert main(["simulate", *RIG, "--out", ""]) == 2
    assert "--out = '': an empty folder name" in capsys.readouterr().err


def test_a_second_writer_gets_one_clear_error(tmp_path, capsys):
    out = tmp_path / "run"
    with folder_lock(out):  # another command is writing there
        assert main(["simulate", *RIG, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert "another drillpy command (pid" in err and str(out) in err and err.count("\n") == 1
        assert not (out / "summary.json").exists()
    assert main(["simulate", *RIG, "--out", str(out)]) == 0  # released: the next one writes
    assert {p.name for p in out.iterdir()} == {"series.csv", "summary.json", "time_series.png"}  # no lock left


def test_a_file_is_replaced_whole_or_not_at_all(tmp_path):
    p = write_text(tmp_path / "a.json", "old")
    with pytest.raises(RuntimeError):
        with replacing(p) as tmp:
            tmp.write_text("half")
            raise RuntimeError("crash while writing")
    assert p.read_text() == "old" and [q.name for q in tmp_path.iterdir()] == ["a.json"]
    write_text(p, "new")
    assert p.read_text() == "new" and LOCK_NAME not in [q.name for q in tmp_path.iterdir()]


def test_ctrl_c_in_a_new_mc_folder_keeps_finished_blocks_and_the_rerun_resumes(tmp_path, monkeypatch, capsys):
    import drillpy.study.store as store
    argv = ["mc", *RIG, "--samples", "4", "--chunk", "2", "--speeds", "8", "--warmup", "0", "--seed", "3",
            "--no-figures", "--json"]
    write_block, written = store.write_block, []

    def interrupted(study, path, lo, values, group=None):
        write_block(study, path, lo, values, group)
        written.append(lo)
        raise KeyboardInterrupt  # Ctrl-C just after the first block is stored
    monkeypatch.setattr(store, "write_block", interrupted)
    out = tmp_path / "new" / "mc"
    assert main([*argv, "--out", str(out)]) == 130
    assert written == [0] and (out / "study.zarr").is_dir()
    assert "kept" in capsys.readouterr().err

    monkeypatch.setattr(store, "write_block", lambda *a, **k: (written.append(a[2]), write_block(*a, **k)))
    assert main([*argv, "--out", str(out)]) == 0
    resumed = json.loads(capsys.readouterr().out)
    assert written == [0, 2]  # only the missing block ran
    assert main([*argv, "--out", str(tmp_path / "once")]) == 0
    once = json.loads(capsys.readouterr().out)
    assert resumed["speeds"] == once["speeds"]  # the same numbers as a run without Ctrl-C


def test_a_refused_second_writer_never_removes_the_folder_it_found_new(tmp_path, capsys):
    from drillpy.cli import removed_on_failure
    out = tmp_path / "race"
    guard = removed_on_failure(out)  # the second command saw no folder yet...
    with folder_lock(out):           # ...then the first created and locked it
        (out / "series.csv").write_text("the first writer's")
        with pytest.raises(ValueError, match="another drillpy command"):
            with guard, folder_lock(out):
                pass
        assert (out / "series.csv").read_text() == "the first writer's"
