"""``/api/leases`` and ``/api/audit``: what the records hold now and how it got there."""

from __future__ import annotations

from fastapi import APIRouter, Query

from polynav.fleet_api.deps import ManagerDep
from polynav.fleet_api.errors import errors
from polynav.fleet_api.schemas import AuditOut, LeaseOut

router = APIRouter(prefix="/api", tags=["records"])


@router.get("/leases", response_model=list[LeaseOut])
def list_leases(manager: ManagerDep) -> list[LeaseOut]:
    """The leases live now (lift cars, doors, corridors), every manager's, by resource."""
    return [LeaseOut.from_domain(lease) for lease in manager.live_leases()]


@router.get("/audit", response_model=list[AuditOut],
            responses=errors({422: "a bad `after` or `limit` (code `validation_error`)"}))
def list_audit(manager: ManagerDep, after: int = Query(default=0, ge=0),
               limit: int = Query(default=500, ge=1, le=5000)) -> list[AuditOut]:
    """The audit trail after entry ``after``, oldest first, at most ``limit`` entries."""
    return [AuditOut.from_domain(e) for e in manager.audit(after=after, limit=limit)]
