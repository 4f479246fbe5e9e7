from __future__ import annotations

import pytest

from polynav.control import registry
from polynav.control.pure_pursuit import PurePursuitConfig, RegulatedPurePursuit
from polynav.errors import ConfigError


def test_regulated_pure_pursuit_is_registered_and_built_with_its_config() -> None:
    cfg = PurePursuitConfig(max_linear_velocity=0.4)
    controller = registry.create("regulated_pure_pursuit", cfg)
    assert isinstance(controller, RegulatedPurePursuit)
    assert controller.config is cfg
    default = registry.create("regulated_pure_pursuit")
    assert isinstance(default, RegulatedPurePursuit)
    assert default.config == PurePursuitConfig()
    assert "regulated_pure_pursuit" in registry.CONTROLLERS


def test_unknown_name_is_a_config_error_listing_the_known_ones() -> None:
    with pytest.raises(ConfigError, match="regulated_pure_pursuit") as err:
        registry.create("dwb")
    assert err.value.key == "control.controller"


def test_config_of_the_wrong_type_is_refused() -> None:
    with pytest.raises(ConfigError) as err:
        registry.create("regulated_pure_pursuit", {"max_linear_velocity": 0.4})
    assert err.value.key == "control.pure_pursuit"
