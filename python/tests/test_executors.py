"""Sweeps spread over executors and parts: `sweep(executor=...)` on a process pool and on a Dask
LocalCluster, and `sweep(shard=...)` merged by `merge`, give the bits of the sweep run in one
process; Ctrl-C cancels the calls not yet started; bad input is refused with ValueError."""

import concurrent.futures
import json

import pytest

import lorentz_gas as lg

# Three points in a field (B = -1, 1, 2 at w = 0.2), and three gaps without one: seconds each.
FIELD = dict(w=0.2, fields=[-1, 1, 2], collisions_per_run=1e5, batches_per_run=4,
             localization_samples=1e4, seed=5, progress=False)
OVER_W = dict(w_from=0.2, w_to=0.3, steps=3, runs=2, collisions_per_run=1e5, batches_per_run=4,
              seed=5, progress=False)


def science(r):
    """The result without what depends on the process: `meta` and `resumed_points`."""
    d = r.to_dict()
    d.pop("meta")
    d.pop("resumed_points")
    return json.dumps(d, sort_keys=True)


@pytest.fixture(scope="module")
def one_process():
    return {"field": science(lg.sweep(**FIELD)), "over_w": science(lg.sweep(**OVER_W))}


def test_a_process_pool_gives_the_bits_of_one_process(one_process):
    with concurrent.futures.ProcessPoolExecutor(max_workers=2) as pool:
        field = lg.sweep(**FIELD, executor=pool)
        over_w = lg.sweep(**OVER_W, executor=pool)
    assert isinstance(field, lg.FieldSweepResult) and isinstance(over_w, lg.SweepResult)
    assert science(field) == one_process["field"]
    assert science(over_w) == one_process["over_w"]


def test_a_dask_local_cluster_gives_the_bits_of_one_process(one_process):
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        executor = client.get_executor()
        field = lg.sweep(**FIELD, executor=executor)
        over_w = lg.sweep(**OVER_W, executor=executor)
    assert science(field) == one_process["field"]
    assert science(over_w) == one_process["over_w"]


def test_parts_on_disk_merge_into_the_bits_of_one_process(one_process, tmp_path):
    parts = [lg.sweep(**FIELD, shard=f"{i}/3", out=tmp_path / f"p{i}") for i in range(3)]
    assert [list(p["points"]) for p in parts] == [[0], [1], [2]]
    assert "part 1/3" in repr(parts[1])
    merged = lg.merge([tmp_path / "p2", tmp_path / "p0", tmp_path / "p1"], out=tmp_path / "m")
    assert isinstance(merged, lg.FieldSweepResult)
    assert science(merged) == one_process["field"]
    assert (tmp_path / "m" / "field-sweep.json").is_file()
    with pytest.raises(ValueError, match=r"1 of 3 points missing.*part 2/3"):
        lg.merge([tmp_path / "p0", tmp_path / "p1"])
    over_w = [lg.sweep(**OVER_W, shard=f"{i}/2", out=tmp_path / f"w{i}") for i in range(2)]
    assert [list(p["points"]) for p in over_w] == [[0, 2], [1]]
    merged = lg.merge([tmp_path / "w0", tmp_path / "w1"])
    assert science(merged) == one_process["over_w"]


class _Pending(concurrent.futures.Executor):
    """An executor whose first call is interrupted (Ctrl-C while waiting for it) and whose
    others never start: what `sweep` does with them is seen on the futures it was given."""

    def __init__(self):
        self.futures = []

    def submit(self, fn, *args, **kwargs):
        f = concurrent.futures.Future()
        if not self.futures:
            f.set_exception(KeyboardInterrupt())
        self.futures.append(f)
        return f


def test_ctrl_c_cancels_the_calls_not_yet_started():
    pool = _Pending()
    with pytest.raises(KeyboardInterrupt):
        lg.sweep(**FIELD, executor=pool)
    assert len(pool.futures) == 3
    assert all(f.cancelled() for f in pool.futures[1:])


def test_bad_input_is_refused_with_value_error(tmp_path):
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        with pytest.raises(ValueError, match="shard and executor"):
            lg.sweep(**FIELD, shard="0/3", executor=pool)
        # Refused in the worker, raised here.
        with pytest.raises(ValueError, match="collisions"):
            lg.sweep(**{**FIELD, "collisions_per_run": 0}, executor=pool)
    with pytest.raises(ValueError, match="concurrent.futures.Executor"):
        lg.sweep(**FIELD, executor=object())
    with pytest.raises(ValueError, match="give out=DIR"):
        lg.sweep(**FIELD, shard="0/3")
    with pytest.raises(ValueError, match="I/N"):
        lg.sweep(**FIELD, shard="3/3", out=tmp_path / "p")
    with pytest.raises(ValueError, match="every part needs a point"):
        lg.sweep(**FIELD, shard="0/4", out=tmp_path / "p")
    with pytest.raises(ValueError, match="sequence of directories"):
        lg.merge(tmp_path)


class _Counting(concurrent.futures.ThreadPoolExecutor):
    """A thread pool that records the part of each call submitted to it."""

    def __init__(self):
        super().__init__(max_workers=1)
        self.parts = []

    def submit(self, fn, *args, **kwargs):
        self.parts.append(args[1]["shard"])
        return super().submit(fn, *args, **kwargs)


def test_an_executor_with_out_computes_only_the_missing_points_and_checks_one_kept(
        one_process, tmp_path):
    out = tmp_path / "s"
    with _Counting() as pool:
        lg.sweep(**OVER_W, out=out, executor=pool)
    assert sorted(pool.parts) == ["0/3", "1/3", "2/3"]
    # Point 1 lost: it is computed, and one of the two kept (drawn at random) again as the check.
    (out / "points" / "point-0001.json").unlink()
    with _Counting() as pool:
        again = lg.sweep(**OVER_W, out=out, executor=pool)
    assert pool.parts[0] == "1/3" and len(pool.parts) == 2 and pool.parts[1] in ("0/3", "2/3")
    assert science(again) == one_process["over_w"]
    assert again["resumed_points"] == 1
    # Only point 0 kept, and edited: it is the one computed again, refused and moved aside.
    for i in (1, 2):
        (out / "points" / f"point-000{i}.json").unlink()
    kept = out / "points" / "point-0000.json"
    text = kept.read_text()
    d = json.loads(text)["runs"][0]["D"]
    kept.write_text(text.replace(repr(d), repr(d * 1.05), 1))
    with _Counting() as pool:
        with pytest.raises(Exception, match="point 0 computed again from its seed"):
            lg.sweep(**OVER_W, out=out, executor=pool)
    assert not kept.exists() and (out / "points" / "point-0000.json.refused").is_file()
