"""`figure` and `reproduce` from Python: the command line's files, bit for bit, and the options a
figure does not take refused."""

import json

import pytest

import lorentz_gas as lg


def test_a_figure_writes_the_command_lines_files(cli, tmp_path):
    r = lg.figure("backscatter-map", w="1/10", particles=20_000, seed=3, out=tmp_path / "py")
    code, _, err = cli("figure", "backscatter-map", "--w", "1/10", "--particles", "2e4",
                       "--seed", "3", "--out", str(tmp_path / "cli"), "--quiet")
    assert code == 0, err
    assert r.files and all(p.endswith(tuple(r.files)) for p in r.paths())
    csv = "fig5-backscatter-map.csv"
    assert csv in r.files
    assert (tmp_path / "py" / csv).read_bytes() == (tmp_path / "cli" / csv).read_bytes()
    data = lambda d: {k: v for k, v in json.loads((d / "fig5-backscatter-map.json").read_text()).items()
                      if k != "meta"}
    assert data(tmp_path / "py") == data(tmp_path / "cli")
    assert "files in" in repr(r)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        (dict(kind="fig9"), "backscatter-map, backscatter, hierarchy"),
        (dict(kind="hierarchy", particles=10), "it takes collisions_per_gap"),
        (dict(kind="backscatter", w=0.1), "only backscatter-map takes w"),
        (dict(kind="backscatter-map", w=0.5), "0.3094"),
        (dict(kind="backscatter-map", particles=0), "particles"),
    ],
)
def test_a_figure_refuses_what_it_does_not_take(kwargs, word, tmp_path):
    with pytest.raises(ValueError, match=word.replace("(", r"\(")):
        lg.figure(out=tmp_path, **kwargs)


def test_reproduce_refuses_an_unknown_budget(tmp_path):
    with pytest.raises(ValueError, match="quick .* or paper"):
        lg.reproduce("huge", out=tmp_path)
