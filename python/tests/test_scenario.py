"""satflock.Scenario: loading, dict and TOML round trips, dotted-key access, and errors that name the
file, the key and the allowed range (the same messages as `satflock run`); numpy arrays as values."""

import numpy as np
import pytest

import satflock


def test_load_builtin_and_read_by_dotted_key():
    s = satflock.Scenario.load("gao-circle")
    assert s.source == "builtin:gao-circle" and s.name == "gao-circle"
    assert s["law.name"] == "bifurcating"
    assert s["satellites.count"] == 50
    assert "law.k_f_kg_per_m_s2" in s and "law.no_such_key" not in s
    with pytest.raises(KeyError):
        s["law.no_such_key"]
    assert "gao-circle" in satflock.Scenario.builtins()


def test_dict_and_toml_round_trips_keep_every_value():
    s = satflock.Scenario.load("hold")
    d = s.to_dict()
    assert satflock.Scenario.from_dict(d).to_dict() == d
    assert satflock.Scenario.from_toml(s.to_toml()).to_dict() == d


def test_set_validates_and_refusals_leave_the_scenario_unchanged(tmp_path):
    s = satflock.Scenario.load("gao-circle")
    s["duration_s"] = np.float64(120.0)  # numpy scalars are taken as their Python value
    s["satellites.count"] = np.int64(20)
    assert s["duration_s"] == 120.0 and s["satellites.count"] == 20
    with pytest.raises(satflock.ScenarioError) as e:
        s["duration_s"] = -1.0
    assert e.value.file == "builtin:gao-circle" and e.value.key == "duration_s"
    assert "allowed" in str(e.value) and "> 0" in str(e.value)
    assert s["duration_s"] == 120.0
    with pytest.raises(satflock.ScenarioError) as e:
        s["law.no_such_key"] = 1.0
    assert e.value.key == "law.no_such_key"
    with pytest.raises(satflock.ScenarioError):
        s["duration_s"] = None
    # Values that must change together: one validation for all.
    s.update({"duration_s": 60.0, "record_interval_s": 5.0})
    assert s["record_interval_s"] == 5.0


def test_a_file_with_an_unknown_key_names_the_file_and_the_line(tmp_path):
    path = tmp_path / "bad.toml"
    text = satflock.Scenario.load("hold").to_toml() + "\nunknown_key_m = 3.0\n"
    path.write_text(text)
    with pytest.raises(satflock.ScenarioError) as e:
        satflock.Scenario.load(str(path))
    assert e.value.file == str(path)
    assert "unknown_key_m" in str(e.value)


def test_an_unknown_name_lists_the_builtins():
    with pytest.raises(satflock.ScenarioError) as e:
        satflock.Scenario.load("no-such-scenario")
    assert "gao-circle" in str(e.value)


def test_a_dict_that_contains_itself_or_nests_too_deep_is_refused():
    d = satflock.Scenario.load("hold").to_dict()
    d["law"]["loop"] = d
    with pytest.raises(satflock.ScenarioError, match=r"`law.loop` contains itself"):
        satflock.Scenario.from_dict(d)
    listed = []
    listed.append(listed)
    with pytest.raises(satflock.ScenarioError, match=r"`events.0.0` contains itself"):
        satflock.Scenario.from_dict({"events": [listed]})
    deep = {}
    node = deep
    for _ in range(20_000):
        node["x"] = {}
        node = node["x"]
    with pytest.raises(satflock.ScenarioError, match=r"nested deeper than 64 levels"):
        satflock.Scenario.from_dict(deep)
    # Within the bound, nesting is just a (here unknown) key.
    with pytest.raises(satflock.ScenarioError, match="unknown field"):
        satflock.Scenario.from_dict({"a": {"b": {"c": 1}}})


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -1.0])
def test_a_bad_value_is_refused_at_construction(value):
    d = satflock.Scenario.load("hold").to_dict()
    d["duration_s"] = value
    with pytest.raises(satflock.ScenarioError) as e:
        satflock.Scenario.from_dict(d)
    assert e.value.key == "duration_s" and "allowed" in str(e.value)
    text = satflock.Scenario.load("hold").to_toml()
    assert "duration_s = 4000.0" in text
    with pytest.raises(satflock.ScenarioError) as e:
        satflock.Scenario.from_toml(text.replace("duration_s = 4000.0", f"duration_s = {value!r}"))
    assert e.value.key == "duration_s"


def test_from_dict_takes_a_numpy_array_of_eme2000_states():
    """Issue 27: the swarm's own inertial states as an (N, 6) numpy array in `satellites.initial`; the
    simulation holds exactly them at t = 0 (to rounding), as the CLI does with the same list."""
    d = satflock.Scenario.load("hold").to_dict()
    hill = satflock.Simulation(satflock.Scenario.from_dict(d))
    states = np.hstack([hill.positions_eci, hill.velocities_eci])  # (N, 6) float64, EME2000
    d["satellites"]["initial"] = {"distribution": "list", "frame": "eme2000", "states": states}
    inertial = satflock.Scenario.from_dict(d)
    assert inertial["satellites.initial.states"] == states.tolist()
    sim = satflock.Simulation(inertial)
    np.testing.assert_allclose(sim.positions_eci, states[:, :3], rtol=0, atol=1e-7)
    np.testing.assert_allclose(sim.velocities_eci, states[:, 3:], rtol=0, atol=1e-10)
    # The same satellites, so the same Hill states.
    np.testing.assert_allclose(sim.positions_hill, hill.positions_hill, rtol=0, atol=1e-7)


def test_a_threat_given_by_an_inertial_state_sits_where_the_state_puts_it():
    """Issue 27: a real object as a threat from Python (`state_eme2000` as a numpy row, propagated by
    the truth dynamics): a threat started on a satellite's own EME2000 state is at that satellite's
    Hill position, and the run's closest approach to it is zero at t = 0."""
    d = satflock.Scenario.load("hold").to_dict()
    base = satflock.Simulation(satflock.Scenario.from_dict(d))
    state = np.concatenate([base.positions_eci[1], base.velocities_eci[1]])
    d["threats"] = [{"name": "twin", "danger_radius_m": 1.0, "state_eme2000": state}]
    d.pop("events", None)
    d["duration_s"] = 60.0
    d["record_interval_s"] = 60.0
    scenario = satflock.Scenario.from_dict(d)
    assert scenario["threats.0.state_eme2000"] == state.tolist()
    result = satflock.run(scenario, progress=False)
    closest = result.summary["environment"]["min_threat_distance_per_satellite_m"][1]
    assert closest == pytest.approx(0.0, abs=1e-6)
