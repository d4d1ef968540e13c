"""The driven gas from Python: ``diffusion(electric=...)`` has the command line's bits and its
result reads like the others."""

import numpy as np
import pytest

import lorentz_gas as lg

from test_same_bits import same


def test_a_run_under_the_thermostat_has_the_command_lines_bits(cli_json):
    args = dict(w="1/5", electric="3/10", electric_angle="-45", collisions=400_000, batches=4,
                seed=5)
    py = lg.diffusion(**args)
    same(py.to_dict(), cli_json("diffusion", *[x for k, v in args.items()
                                               for x in ("--" + k.replace("_", "-"), str(v))]))
    assert isinstance(py, lg.CurrentResult)
    assert "J/E" in repr(py) and "E = 0.3" in repr(py)
    assert str(py).startswith("periodic Lorentz gas under a thermostatted electric field")
    # The direction of the exact angle −45°: π/4 and its cosine and sine rounded, then
    # normalised, a few units in the last place of √½ (4.4e-16 is four).
    assert np.allclose(py.direction, [np.sqrt(0.5), -np.sqrt(0.5)], rtol=0, atol=4.4e-16)
    angles = py.to_pandas("angles")
    assert len(angles) == len(py.angle_bins) == 72
    # A density per radian: it integrates to 1 over the circle.
    assert abs(np.sum(py.angle_density) * 2 * np.pi / 72 - 1) < 1e-12
    assert len(py.to_pandas("batches")) == 4


def test_a_zero_electric_field_is_the_run_without_a_field():
    a = lg.diffusion(w="0.1", collisions=2e6, batches=4, seed=3)
    b = lg.diffusion(w="0.1", collisions=2e6, batches=4, seed=3, electric="0", electric_angle=30)
    assert isinstance(b, lg.DiffusionResult) and list(a.batch_D) == list(b.batch_D)


@pytest.mark.parametrize("kwargs, message", [
    (dict(electric="11"), r"0 < \|E\| <= 10"),
    (dict(electric="1", electric_angle="400"), "-360 to 360"),
    (dict(electric="x"), "electric"),
    (dict(electric="1", field="1"), "one motion|both"),
    (dict(electric="1", scene="square", radius="1/4", w=None), "corridor|horizon"),
])
def test_bad_fields_are_value_errors(kwargs, message):
    args = dict(w="0.2", collisions=2e5, batches=4)
    args.update(kwargs)
    if args.get("w") is None:
        args.pop("w")
    with pytest.raises(ValueError, match=message):
        lg.diffusion(**args)
