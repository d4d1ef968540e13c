"""The examples in the package's docstrings run and print what they say."""

import doctest

import pytest

import lorentz_gas
import lorentz_gas._drawing


@pytest.mark.parametrize("module", [lorentz_gas, lorentz_gas._drawing])
def test_docstring_examples_run(module):
    pytest.importorskip("matplotlib")
    result = doctest.testmod(module)
    assert result.attempted > 0 and result.failed == 0, result
