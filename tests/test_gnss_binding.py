"""The engine's binding (``gnssatt._core.gnss_run``, ``GnssEngine``): every malformed input refused with a
message naming it, before any work; the options' errors name the CLI option; results are frozen."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from gnssatt import _core
from gnssatt.errors import InvalidInputError

N_RX, N_EP, SATS = 2, 3, ["G01", "R07", "E11"]


def _arrays(n_rx: int = N_RX, n_ep: int = N_EP, n_sat: int = len(SATS)) -> dict[str, Any]:
    shape = (n_rx, n_ep, n_sat, 3)
    nan = np.full(shape, np.nan)
    return {
        "time_gpst_ns": np.arange(n_ep, dtype=np.int64) * 1_000_000_000 + 1_400_000_000_000_000_000,
        "sats": list(SATS[:n_sat]),
        "glonass_channel": np.array([99, -3, 99][:n_sat], dtype=np.int64),
        "code_m": nan,
        "phase_cycles": nan.copy(),
        "doppler_hz": nan.copy(),
        "snr_dbhz": nan.copy(),
        "lli": np.zeros(shape, np.uint8),
        "approx_position_m": np.full((n_rx, 3), np.nan),
    }


def _run(options: dict[str, Any] | None = None, **replace: Any) -> Any:
    a = _arrays()
    a.update(replace)
    return _core.gnss_run(
        _core.ObservationArrays(**a), _core.Navigation(), _core.GnssOptions(**(options or {}))
    )


@pytest.mark.parametrize(
    ("replace", "says"),
    [
        ({"sats": ["G01", "X07", "E11"]}, "sats[1] as a system letter among GRECJ"),
        ({"sats": ["G01", "R", "E11"]}, "sats[1]"),
        ({"sats": ["G01", "R00", "E11"]}, "sats[1]"),
        ({"glonass_channel": np.array([99, 9, 99])}, "glonass_channel[1] (R07) in -7..6, or 99"),
        ({"glonass_channel": np.array([99, 99])}, "glonass_channel of shape (3)"),
        ({"code_m": np.full((2, 2, 3, 3), np.nan)}, "code_m of shape (2, 3, 3, 3)"),
        ({"lli": np.zeros((2, 3, 3, 2), np.uint8)}, "lli of shape (2, 3, 3, 3)"),
        ({"approx_position_m": np.full((3, 3), np.nan)}, "approx_position_m of shape (2, 3)"),
        ({"approx_position_m": np.array([[1e6, np.nan, 0.0], [np.nan] * 3])}, "approx_position_m[0] finite"),
        ({"code_m": np.full((2, 3, 3, 3), np.inf)}, "code_m"),
        ({"time_gpst_ns": np.array([3, 2, 1], dtype=np.int64)}, "strictly increasing"),
        ({"sats": ["G01", "G01", "E11"]}, "each satellite once"),
    ],
)
def test_malformed_observations_are_named(replace: dict[str, Any], says: str) -> None:
    with pytest.raises(InvalidInputError) as err:
        _run(**replace)
    assert says in str(err.value)


def test_one_receiver_is_refused() -> None:
    a = _arrays(n_rx=1)
    with pytest.raises(InvalidInputError, match="two or more receivers, got 1"):
        _core.gnss_run(_core.ObservationArrays(**a), _core.Navigation())


@pytest.mark.parametrize(
    ("options", "says"),
    [
        ({"systems": "GX"}, "systems as letters among GRECJ"),
        ({"systems": ""}, "--systems"),
        ({"frequencies": 4}, "--frequencies"),
        ({"frequencies": 0}, "--frequencies"),
        ({"elevation_mask_deg": 91.0}, "--elevation-mask"),
        ({"min_success_rate": 1.5}, "--min-success-rate"),
        ({"ratio_threshold": 0.5}, "--ratio-threshold"),
        ({"base_position_m": np.zeros(3)}, "--base-position"),
        ({"base_position_m": np.zeros(2)}, "base_position_m of shape (3,)"),
        ({"motion": "flying"}, "motion 'static' or 'moving'"),
        ({"method": "best"}, "method 'auto', 'ml' or 'lambda'"),
        ({"body_baselines_m": np.zeros((2, 3))}, "one body baseline per rover (1), got 2"),
        ({"body_baselines_m": np.full((1, 3), np.nan)}, "body_baselines_m contains a non-finite value"),
        ({"step_deg": -1.0}, "--step"),
        ({"window_deg": 0.0}, "--window"),
    ],
)
def test_bad_options_name_the_option(options: dict[str, Any], says: str) -> None:
    with pytest.raises(InvalidInputError) as err:
        _run(options)
    assert says in str(err.value)


def test_engine_checks_its_arrays_against_the_constructor() -> None:
    with pytest.raises(InvalidInputError, match="n_receivers >= 2, got 1"):
        _core.GnssEngine(SATS, np.array([99, -3, 99]), 1, _core.Navigation())
    with pytest.raises(InvalidInputError, match="--frequencies"):
        _core.GnssEngine(
            SATS, np.array([99, -3, 99]), 2, _core.Navigation(), _core.GnssOptions(frequencies=5)
        )


def test_engine_refuses_observations_unlike_its_constructor() -> None:
    engine = _core.GnssEngine(SATS, np.array([99, -3, 99]), 2, _core.Navigation())
    with pytest.raises(InvalidInputError, match="constructor's satellites and GLONASS channels"):
        engine.process(_core.ObservationArrays(**_arrays(n_sat=2)))
    with pytest.raises(InvalidInputError, match="constructor's satellites and GLONASS channels"):
        engine.process(_core.ObservationArrays(**{**_arrays(), "glonass_channel": np.array([99, 99, 99])}))
    with pytest.raises(InvalidInputError, match="n_receivers = 2 receivers, got 3"):
        engine.process(_core.ObservationArrays(**_arrays(n_rx=3)))


def test_observation_arrays_are_keyword_only_frozen_and_described() -> None:
    with pytest.raises(TypeError, match="positional"):
        _core.ObservationArrays(*_arrays().values())  # type: ignore[misc]
    obs = _core.ObservationArrays(**_arrays())
    assert (obs.receivers, obs.epochs, obs.sats) == (N_RX, N_EP, list(SATS))
    with pytest.raises(AttributeError):
        obs.receivers = 1  # type: ignore[misc]
    assert repr(obs) == f"ObservationArrays(receivers={N_RX}, epochs={N_EP}, sats={list(SATS)!r})"


def test_defaults_are_the_engines() -> None:
    # options.rs: EngineOptions::default (the one place the defaults live)
    assert _core.GNSS_DEFAULT_RATIO_THRESHOLD == 3.0
    assert _core.GNSS_DEFAULT_ELEVATION_MASK_DEG == pytest.approx(10.0)
    assert _core.GNSS_DEFAULT_MIN_SUCCESS_RATE == 0.5  # the gate study of docs/observation_engine.md
    assert _core.GNSS_MAX_FREQUENCIES == 3


@pytest.mark.slow
def test_streaming_is_the_session_call_in_pieces() -> None:
    """gnss_run is GnssEngine fed every epoch at once (DESIGN16: one mechanism): feeding the GEONET pair
    in two blocks gives the same epochs, held integers carried across the cut."""
    from gnssatt.data import geonet_dir
    from gnssatt.gnss.session_input import session_input
    from gnssatt.rinex import read_nav, read_obs
    from gnssatt.rinex.nav import nav_input

    d = geonet_dir()
    nav = read_nav(d / "07590920.05n")
    si = session_input([read_obs(d / "07590920.05o"), read_obs(d / "30400920.05o")], frequencies=2, nav=nav)
    ni = nav_input(nav)
    opts: dict[str, Any] = {"systems": "G", "frequencies": 2, "motion": "moving", "continuity": True}
    opts["method"] = "lambda"
    navigation = ni.navigation()
    session = _core.gnss_run(si.observations(), navigation, _core.GnssOptions(**opts))

    # gnss_run calibrates the code noise on the first epochs before solving them, which a stream cannot
    # (docs/observation_engine.md): the whole session is one engine fed every epoch in one call.
    def engine() -> Any:
        return _core.GnssEngine(list(si.sats), si.glonass_channel, 2, navigation, _core.GnssOptions(**opts))

    whole = engine().process(si.observations())
    streamed = engine()
    parts = [streamed.process(si.observations(slice(a, b))) for a, b in ((0, 50), (50, len(si.time_gpst_ns)))]
    assert parts[0].double_differences is None and session.double_differences.shape == (5, 3)
    np.testing.assert_array_equal(session.time_gpst_ns, whole.time_gpst_ns)
    for name in ("time_gpst_ns", "fixed", "angles_deg", "baselines_enu_m", "satellites_per_system"):
        np.testing.assert_array_equal(np.concatenate([getattr(p, name) for p in parts]), getattr(whole, name))
    with pytest.raises(AttributeError):
        whole.fixed = None  # frozen


def test_the_size_limit_is_checked_before_any_copy() -> None:
    """1.2e8 epoch x satellite x receiver cells (limit 1e8, observations.rs) as zero-stride views: refused
    before the binding copies anything (a copy would take gigabytes)."""
    from gnssatt.errors import WorkLimitError

    n_ep = 20_000_000
    big = np.broadcast_to(np.float64(np.nan), (2, n_ep, 3, 3))
    a = _arrays()
    a.update(
        time_gpst_ns=np.broadcast_to(np.int64(0), (n_ep,)),
        code_m=big,
        phase_cycles=big,
        doppler_hz=big,
        snr_dbhz=big,
        lli=np.broadcast_to(np.uint8(0), (2, n_ep, 3, 3)),
    )
    with pytest.raises(WorkLimitError, match="observations"):
        _core.ObservationArrays(**a)


def test_options_are_checked_when_made_and_shown() -> None:
    """One typed options object: errors when it is made, naming the CLI option; defaults for None."""
    with pytest.raises(InvalidInputError, match="--min-success-rate"):
        _core.GnssOptions(min_success_rate=1.5)
    with pytest.raises(InvalidInputError, match="GRECJ"):
        _core.GnssOptions(systems="GX")
    with pytest.raises(TypeError):
        _core.GnssOptions("G")  # keyword-only
    shown = repr(_core.GnssOptions(systems="GE", max_failure_rate=1e-3))
    assert shown.startswith("GnssOptions(") and "Galileo" in shown and "max_failure_rate: 0.001" in shown
