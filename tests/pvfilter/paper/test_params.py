"""FilterParams: Table I defaults and "field: message" validation."""

import dataclasses
import math

import pytest

from pvfilter import FilterParams


def test_defaults_are_table_one():
    params = FilterParams()
    table_one = dict(
        d_th=0.3,
        m_th=10,
        v_th=0.65,
        sigma_theta=1.0,
        sigma_l=1.0,
        p_th=0.8,
        d_track=1.5,
        d_min=0.3,
        d_max=2.0,
        size_ratio_min=0.5,
        size_ratio_max=2.0,
    )
    assert {name: getattr(params, name) for name in table_one} == table_one
    assert params.clustering == "scan_order" and params.tracking is True


def test_params_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        FilterParams().d_th = 1.0


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("d_th", -1.0),
        ("d_th", 0.0),
        ("d_th", math.inf),
        ("m_th", 0),
        ("m_th", 2.5),
        ("m_th", True),
        ("v_th", 1.5),
        ("v_th", -0.1),
        ("sigma_theta", 0.0),
        ("sigma_l", math.nan),
        ("p_th", 1.01),
        ("d_track", -0.1),
        ("d_min", -0.1),
        ("d_max", 0.2),
        ("size_ratio_min", 0.0),
        ("size_ratio_max", 0.4),
        ("clustering", "kmeans"),
        ("tracking", "yes"),
        ("d_th", "0.3"),
    ],
)
def test_invalid_value_raises_value_error_starting_with_the_field_name(field, value):
    with pytest.raises(ValueError) as error:
        FilterParams(**{field: value})
    assert str(error.value).startswith(f"{field}: ")


def test_message_states_expectation_and_value():
    with pytest.raises(ValueError, match=r"^d_th: must be > 0 m, got -1$"):
        FilterParams(d_th=-1)
    with pytest.raises(ValueError, match=r"^d_max: must be > d_min \(0.3 m\), got 0.2$"):
        FilterParams(d_max=0.2)


def test_infinite_gates_switch_checks_off():
    params = FilterParams(d_track=math.inf, d_max=math.inf, size_ratio_max=math.inf)
    assert params.d_track == math.inf
