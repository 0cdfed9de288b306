"""The examples in the package's docstrings run and print what they say."""

import doctest

import pytest

import mcint._integrate
import mcint._multilevel
import mcint._sensitivity
import mcint.qmc


@pytest.mark.parametrize("module", [mcint._integrate, mcint._multilevel, mcint._sensitivity, mcint.qmc])
def test_docstring_examples(module):
    failures, tried = doctest.testmod(module, verbose=False)
    assert tried > 0 and failures == 0
