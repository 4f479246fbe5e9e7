"""polynav's own REST + WebSocket API (FastAPI), the native dialect every other one mirrors.

``create_app(runtime, config)`` builds the application; ``polynav run`` serves it with uvicorn.
"""

from __future__ import annotations

from polynav.api.app import create_app
from polynav.api.config import ApiConfig

__all__ = ["ApiConfig", "create_app"]
