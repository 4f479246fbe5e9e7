"""One APIRouter per resource of the native API."""
