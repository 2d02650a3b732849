"""A model-file record spoiled one way must be refused by name: the shared body of the hostile
model-file cases of the measured-PSD, IAAFT and 2-D spectral-mixture tests."""

from __future__ import annotations

import copy

import pytest

from roughgp.surface_models.model import FittedModel, ModelFileError


def assert_refused(record, spoil, words) -> None:
    """``spoil`` a deep copy of ``record`` (a model file's dict); reading it must raise
    :class:`ModelFileError` whose message holds ``words``."""
    record = copy.deepcopy(record)
    spoil(record)
    with pytest.raises(ModelFileError) as info:
        FittedModel.from_dict(record)
    assert words in str(info.value)
