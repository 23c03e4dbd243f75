"""The medians the filter takes give ``np.median``'s very values."""

import collections
import math

import numpy as np
import pytest

from pvfilter.improved.medians import median_in_place, median_of_few


@pytest.mark.parametrize("size", [1, 2, 3, 4, 25, 700, 701])
def test_a_sorted_few_give_np_medians_values(size):
    rng = np.random.default_rng(size)
    for _ in range(20):
        values = rng.normal(0.0, 0.01, size).round(rng.integers(2, 6))  # ties too
        expected = float(np.median(values))
        assert median_of_few(values.tolist()) == expected
        assert median_of_few(collections.deque(values.tolist())) == expected


@pytest.mark.parametrize("size", [1, 2, 3, 4, 700, 701])
def test_a_partition_in_place_gives_np_medians_values(size):
    rng = np.random.default_rng(size)
    for _ in range(20):
        values = np.abs(rng.normal(0.0, 0.01, size).round(rng.integers(2, 6)))
        expected = float(np.median(values))
        assert median_in_place(values.copy()) == expected


def test_nan_among_a_few_gives_nan_as_np_median_does():
    assert math.isnan(median_of_few([0.1, float("nan"), 0.3]))


def test_no_values_have_no_median():
    with pytest.raises(ValueError, match="no values"):
        median_of_few([])
    with pytest.raises(ValueError, match="no values"):
        median_in_place(np.zeros(0))
