"""docs/report-schema.md lists every field of report.json, and the version
fields hold what it says."""

import re

import numpy as np

import fss
from conftest import SOURCE_DIR


def field_paths(value, prefix=""):
    """Dotted paths of every object key, e.g. 'metrics.rmse'."""
    paths = []
    if isinstance(value, dict):
        for key, item in value.items():
            path = f"{prefix}.{key}" if prefix else key
            paths.append(path)
            paths += field_paths(item, path)
    return paths


def test_schema_document_lists_every_field():
    image = np.tile(np.arange(600.0) % 256, (12, 1))
    report = fss.simulate(image, data_range=255, code="snapshot", trials=2).report
    documented = set(re.findall(r"`([a-z0-9_.]+)`", (SOURCE_DIR / "docs/report-schema.md").read_text()))
    missing = [path for path in field_paths(report) if path not in documented]
    assert not missing, f"not in docs/report-schema.md: {missing}"
    assert f"schema version {report['schema_version']}" in (
        SOURCE_DIR / "docs/report-schema.md").read_text()


def test_version_fields():
    image = np.tile(np.arange(600.0) % 256, (12, 1))
    report = fss.simulate(image, data_range=255, code="snapshot").report
    assert isinstance(report["schema_version"], int) and report["schema_version"] == 1
    assert re.fullmatch(r"\d+\.\d+\.\d+( \(git [0-9a-f]+(-dirty)?\))?", report["fssim_version"])
