import os

os.environ.setdefault("MPLBACKEND", "Agg")


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "slow: heavier cases left out of the default run (-m slow)"
    )
    config.addinivalue_line(
        "markers",
        "stress: the full numerical stress matrix (tests/stress; run with -m stress)",
    )


def pytest_collection_modifyitems(config, items):
    """Leave ``slow`` and ``stress`` tests out of the default run; any ``-m``
    expression (``-m stress``, ``-m "slow or not slow"``) selects them as
    usual."""
    if config.option.markexpr:
        return
    import pytest

    skip = pytest.mark.skip(reason="heavy: select with -m slow / -m stress")
    for item in items:
        if item.get_closest_marker("slow") or item.get_closest_marker("stress"):
            item.add_marker(skip)
