"""Scenario files: the shipped ones load, malformed ones fail with the file and the key."""

from pathlib import Path

import pytest

from twsb_sim.config_errors import ConfigError
from twsb_sim.scenario import load_scenario

SCENARIOS = sorted((Path(__file__).resolve().parents[2] / "scenarios").glob("*.toml"))
MINIMAL = "duration_s = 2.0\n"


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    return path


def error_for(tmp_path: Path, text: str) -> ConfigError:
    with pytest.raises(ConfigError) as caught:
        load_scenario(write(tmp_path, text))
    assert str(caught.value).startswith(str(tmp_path / "bad.toml"))
    return caught.value


def test_the_paper_scenarios_are_shipped():
    names = {p.stem for p in SCENARIOS}
    assert {
        "hard_stop",
        "shove",
        "normal_sequence",
        "disturb_sequence",
        "house1_single",
        "house2_multi",
    } <= names


@pytest.mark.parametrize("path", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_shipped_scenario_loads(path):
    scenario = load_scenario(path)
    assert scenario.name and scenario.duration_s > 0
    assert all(
        abs(c.velocity_mps) <= 1.0 and abs(c.yaw_rate_rad_s) <= 0.6 for c in scenario.commands
    )


def test_minimal_scenario_has_defaults(tmp_path):
    scenario = load_scenario(write(tmp_path, MINIMAL))
    assert scenario.name == "bad"
    assert scenario.house.name == "house1"
    assert scenario.robot.lidar_height_m == 0.25


def test_overrides_reach_the_configs(tmp_path):
    scenario = load_scenario(
        write(
            tmp_path,
            MINIMAL
            + "[robot]\nlidar_height_m = 0.3\n[lidar]\nrange_noise_std_m = 0\n[house]\nseed = 4\n",
        )
    )
    assert scenario.robot.lidar_height_m == 0.3
    assert scenario.lidar.range_noise_std_m == 0.0
    assert scenario.house.seed == 4 and scenario.house.name is None


def test_sensor_tables_reach_the_configs(tmp_path):
    text = MINIMAL + (
        "[lidar]\nsweep = 'instant'\nrotation = 'clockwise'\n"
        "[imu]\nrate_hz = 400.0\nlatency_s = 0.01\n"
        "[attitude]\ntime_constant_s = 1.5\n"
        "[odometry]\nrate_hz = 20.0\nencoder_counts_per_rev = 4096\n"
    )
    scenario = load_scenario(write(tmp_path, text))
    assert (scenario.lidar.sweep, scenario.lidar.rotation) == ("instant", "clockwise")
    assert (scenario.imu.rate_hz, scenario.imu.latency_s) == (400.0, 0.01)
    assert scenario.attitude.time_constant_s == 1.5
    assert (scenario.odometry.rate_hz, scenario.odometry.encoder_counts_per_rev) == (20.0, 4096)


@pytest.mark.parametrize(
    ("text", "key", "expected"),
    [
        ("duration_s = 2\nspeed = 3\n", "speed", "unknown key"),
        ("name = 'x'\n", "duration_s", "missing"),
        ("duration_s = 'long'\n", "duration_s", "expected a number"),
        ("duration_s = -1.0\n", "duration_s", "expected 0 < duration_s"),
        (MINIMAL + "[robot]\nlidar_hieght_m = 0.3\n", "robot.lidar_hieght_m", "unknown key"),
        (MINIMAL + "[robot]\nlidar_height_m = true\n", "robot.lidar_height_m", "expected a number"),
        (MINIMAL + "[robot]\nbody_mass_kg = -2.0\n", "robot.body_mass_kg", "expected"),
        (MINIMAL + "[lidar]\nrange_max_m = 0.01\n", "lidar.", ""),
        (MINIMAL + "[[commands]]\nvelocity_mps = 1.0\n", "commands[0].t_s", "missing"),
        (
            MINIMAL + "[[commands]]\nt_s = 1.0\nvelocity_mps = 9.0\n",
            "commands[0].velocity_mps",
            "expected -2 to 2",
        ),
        (
            MINIMAL + "[[commands]]\nt_s = 1.0\nramp_s = 0.5\n[[commands]]\nt_s = 1.2\n",
            "commands[1].t_s",
            "times out of order",
        ),
        (MINIMAL + "[[commands]]\nt_s = 5.0\n", "commands[0].t_s", "expected 0 to 2 s"),
        (MINIMAL + "[[shoves]]\nt_s = 1.0\nforce_n = [1, 2]\n", "shoves[0].force_n", "array of 3"),
        (
            MINIMAL + "[[shoves]]\nt_s = 1.0\nforce_n = [900, 0, 0]\n",
            "shoves[0].force_n",
            "N (magnitude)",
        ),
        (MINIMAL + "[house]\nname = 'house1'\nseed = 3\n", "house.name", "exactly one"),
        (MINIMAL + "commands = 3\n", "commands", "array of tables"),
        (MINIMAL + "[lidar]\nsweep = 'global'\n", "lidar.sweep", "expected one of"),
        (MINIMAL + "[lidar]\nrotation = 'cw'\n", "lidar.rotation", "expected one of"),
        (
            MINIMAL + "[lidar]\ndropout_probability = 2.0\n",
            "lidar.dropout_probability",
            "expected 0 to 1",
        ),
        (MINIMAL + "[imu]\nrate_hz = 1000.0\n", "imu.rate_hz", "expected 10 to 500 Hz"),
        (MINIMAL + "[imu]\ngyro_noise = 0.1\n", "imu.gyro_noise", "unknown key"),
        (
            MINIMAL + "[attitude]\ntime_constant_s = 0\n",
            "attitude.time_constant_s",
            "expected a value > 0",
        ),
        (
            MINIMAL + "[odometry]\nencoder_counts_per_rev = 10.5\n",
            "odometry.encoder_counts_per_rev",
            "expected an integer",
        ),
        (
            MINIMAL + "[robot]\nlidar_tilt_pitch_deg = 30.0\n",
            "robot.lidar_tilt_pitch_deg",
            "expected a value in",
        ),
    ],
)
def test_malformed_scenario_names_file_and_key(tmp_path, text, key, expected):
    error = error_for(tmp_path, text)
    assert key in error.key if key.endswith(".") else error.key == key
    assert expected in str(error)


def test_invalid_toml_is_a_config_error(tmp_path):
    assert "not valid TOML" in str(error_for(tmp_path, "duration_s = \n"))


def test_missing_file(tmp_path):
    with pytest.raises(ConfigError, match="no such scenario file"):
        load_scenario(tmp_path / "nope.toml")
