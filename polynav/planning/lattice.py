"""A lattice search over position and heading for a body that is not a disk (numba kernels).

A grid planner that inflates obstacles by the inscribed radius plans for a disk: it routes a
rectangle through any gap wider than the rectangle's width, including gaps narrower than its
diagonal that the body can take only lined up with them, and gaps it can never reach lined up
because there is no room to turn before them. This search plans for the body itself.

**States** are ``(ix, iy, k)``: a cell and one of 16 headings. The headings are the directions
of the 16 moves ``(±1, 0), (±2, ±1), (±1, ±1), (±1, ±2), (0, ±1)``, so a differential-drive base
either drives *forward along its heading* to the next lattice cell (``k`` unchanged) or *turns in
place* to the neighbouring heading (``k ± 1``) (the motion primitives of a diff-drive state
lattice, as Nav2's Smac lattice planner offers them). Driving along its own axis by less than
its length, a convex body sweeps exactly the union of its two end placements, so a move is
checked by its end state alone; a turn in place is checked along the sweep
(:meth:`~polynav.footprint.Footprint.rotation_step`).

**A state is free** when its cell is passable for the centre (below INSCRIBED, as the grid
planner's table says) and, if the cell lies within the circumscribed radius of an obstacle
(``near``), the footprint placed there at that heading overlaps no LETHAL cell. Checks run
lazily, once per state, so the search pays only for the states it reaches.

**Costs** are the grid planner's: each move's length [cells] times the multiplier of the cell
entered, plus ``turn_cost`` [cells per radian] for turning in place. The heuristic is a 2-D
cost-to-go (:func:`cost_to_go`, 8-connected, from the goal over the same table): a relaxation
of the body's problem, slightly inadmissible against the 16-direction moves (a knight move is
at most 8 % shorter than its 8-connected equivalent), which bounds the result within 8 % of the
cheapest lattice route and keeps the search narrow.

The lattice route is then *shortened* (:func:`shorten`): from each vertex, the farthest later
state reached by a straight segment along which the body, facing along it, stays free, the
turn onto it at the vertex is free, and the segment costs no more than the lattice route it
replaces. The result is a polyline of straight legs joined by turns the body can make, which
is what the controller checks it against.

All coordinates here are cells of the grid's own frame (origin at the corner of cell (0, 0)).
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.footprint.kernels import NO_CELLS, overlaps_at, reach_of

HEADINGS = 16
MOVE_DX = np.array([1, 2, 1, 1, 0, -1, -1, -2, -1, -2, -1, -1, 0, 1, 1, 2], dtype=np.int64)
MOVE_DY = np.array([0, 1, 1, 2, 1, 2, 1, 1, 0, -1, -1, -2, -1, -2, -1, -1], dtype=np.int64)
ANGLES = np.arctan2(MOVE_DY.astype(np.float64), MOVE_DX.astype(np.float64))
"""Heading ``k`` [rad, grid frame] is the direction of move ``k``; counter-clockwise order."""

_UNSEEN, _FREE, _BLOCKED = 0, 1, 2


def nearest_heading(theta: float) -> int:
    """The lattice heading closest to ``theta`` [rad, grid frame]."""
    diff = np.abs(np.angle(np.exp(1j * (ANGLES - theta))))
    return int(np.argmin(diff))


@numba.njit(cache=True, nogil=True)
def _passable(grid: npt.NDArray[np.uint8], mult: npt.NDArray[np.float64], ix: int, iy: int
              ) -> bool:
    h, w = grid.shape
    if ix < 0 or iy < 0 or ix >= w or iy >= h:
        return False
    return math.isfinite(mult[grid[iy, ix]])


@numba.njit(cache=True, nogil=True)
def _body_free(
    grid: npt.NDArray[np.uint8],
    near: npt.NDArray[np.bool_],
    res: float,
    verts: npt.NDArray[np.float64],
    reach: float,
    x: float,
    y: float,
    theta: float,
    world: npt.NDArray[np.float64],
    ignore: npt.NDArray[np.int64],
) -> bool:
    """The body at (x, y, theta) [cells] overlaps no LETHAL cell outside ``ignore`` (checked
    only when ``near``)."""
    ix, iy = int(math.floor(x)), int(math.floor(y))
    h, w = near.shape
    if 0 <= ix < w and 0 <= iy < h and not near[iy, ix]:
        return True
    return not overlaps_at(grid, res, verts, 0.0, x * res, y * res, theta, reach, False, world,
                           ignore)


@numba.njit(cache=True, nogil=True)
def _body_for(
    verts: npt.NDArray[np.float64],
    padded: npt.NDArray[np.float64],
    dx: int,
    dy: int,
    near2: float,
) -> npt.NDArray[np.float64]:
    """The exact body ``dx``, ``dy`` [cells] from the start (within ``sqrt(near2)``), else the
    padded one: the robot is not asked for room it has not got where it stands."""
    return verts if dx * dx + dy * dy <= near2 else padded


@numba.njit(cache=True, nogil=True)
def _turn_free(
    grid: npt.NDArray[np.uint8],
    near: npt.NDArray[np.bool_],
    res: float,
    verts: npt.NDArray[np.float64],
    reach: float,
    x: float,
    y: float,
    a0: float,
    a1: float,
    step: float,
    world: npt.NDArray[np.float64],
    ignore: npt.NDArray[np.int64],
) -> bool:
    """The turn in place at (x, y) from ``a0`` to ``a1`` [rad] the short way is free (ends
    excluded: states check their own)."""
    d = a1 - a0
    while d > math.pi:
        d -= 2.0 * math.pi
    while d < -math.pi:
        d += 2.0 * math.pi
    n = int(math.ceil(abs(d) / step))
    for i in range(1, n):
        if not _body_free(grid, near, res, verts, reach, x, y, a0 + d * i / n, world, ignore):
            return False
    return True


@numba.njit(cache=True, nogil=True)
def _heap_push(keys: npt.NDArray[np.float64], vals: npt.NDArray[np.int64], n: int, key: float,
               val: int) -> None:
    j = n
    while j > 0:
        parent = (j - 1) >> 1
        if keys[parent] <= key:
            break
        keys[j] = keys[parent]
        vals[j] = vals[parent]
        j = parent
    keys[j] = key
    vals[j] = val


@numba.njit(cache=True, nogil=True)
def _heap_pop(keys: npt.NDArray[np.float64], vals: npt.NDArray[np.int64], n: int) -> None:
    """Remove the top of a heap of ``n`` entries (the caller reads it first)."""
    last_key, last_val = keys[n - 1], vals[n - 1]
    m = n - 1
    j = 0
    while True:
        c = 2 * j + 1
        if c >= m:
            break
        if c + 1 < m and keys[c + 1] < keys[c]:
            c += 1
        if keys[c] >= last_key:
            break
        keys[j] = keys[c]
        vals[j] = vals[c]
        j = c
    if m > 0:
        keys[j] = last_key
        vals[j] = last_val


@numba.njit(cache=True, nogil=True)
def _grown(
    keys: npt.NDArray[np.float64], vals: npt.NDArray[np.int64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """A full heap's arrays, copied into twice the room."""
    n = keys.shape[0]
    more_keys = np.empty(2 * n, dtype=np.float64)
    more_vals = np.empty(2 * n, dtype=np.int64)
    more_keys[:n] = keys
    more_vals[:n] = vals
    return more_keys, more_vals


@numba.njit(cache=True, nogil=True)
def cost_to_go(
    grid: npt.NDArray[np.uint8],
    mult: npt.NDArray[np.float64],
    gx: int,
    gy: int,
    x0: int,
    y0: int,
    x1: int,
    y1: int,
) -> npt.NDArray[np.float64]:
    """8-connected cheapest cost [cells] from every cell of the window ``[x0, x1) x [y0, y1)``
    to the goal cell (Dijkstra from the goal, no corner cutting); ``inf`` where unreachable."""
    w, h = x1 - x0, y1 - y0
    dist = np.full((h, w), np.inf)
    done = np.zeros((h, w), dtype=np.bool_)
    keys = np.empty(1024, dtype=np.float64)
    vals = np.empty(1024, dtype=np.int64)
    n = 0
    if gx < x0 or gy < y0 or gx >= x1 or gy >= y1:
        return dist
    dist[gy - y0, gx - x0] = 0.0
    keys[0] = 0.0
    vals[0] = (gy - y0) * w + (gx - x0)
    n = 1
    sq2 = math.sqrt(2.0)
    while n > 0:
        d = keys[0]
        v = vals[0]
        _heap_pop(keys, vals, n)
        n -= 1
        ly, lx = v // w, v % w
        if done[ly, lx]:
            continue
        done[ly, lx] = True
        for dy in range(-1, 2):
            for dx in range(-1, 2):
                if dx == 0 and dy == 0:
                    continue
                nx, ny = lx + dx, ly + dy
                if nx < 0 or ny < 0 or nx >= w or ny >= h or done[ny, nx]:
                    continue
                # The step is priced by the cell it leaves toward the goal (the search's move
                # enters this one), so the figure is the reverse search's exact cost.
                m = mult[grid[ly + y0, lx + x0]]
                if not math.isfinite(mult[grid[ny + y0, nx + x0]]) or not math.isfinite(m):
                    continue
                if dx != 0 and dy != 0:
                    if not (math.isfinite(mult[grid[ly + y0, nx + x0]])
                            and math.isfinite(mult[grid[ny + y0, lx + x0]])):
                        continue
                    nd = d + sq2 * m
                else:
                    nd = d + m
                if nd < dist[ny, nx]:
                    dist[ny, nx] = nd
                    if n == keys.shape[0]:
                        keys, vals = _grown(keys, vals)
                    _heap_push(keys, vals, n, nd, ny * w + nx)
                    n += 1
    return dist


@numba.njit(cache=True, nogil=True)
def search(
    grid: npt.NDArray[np.uint8],
    mult: npt.NDArray[np.float64],
    near: npt.NDArray[np.bool_],
    res: float,
    verts: npt.NDArray[np.float64],
    rot_step: float,
    turn_cost: float,
    h: npt.NDArray[np.float64],
    x0: int,
    y0: int,
    sx: int,
    sy: int,
    sk: int,
    gx: int,
    gy: int,
    max_expansions: int,
    start_ignore: npt.NDArray[np.int64],
    padded: npt.NDArray[np.float64],
    exact_within: float,
) -> tuple[npt.NDArray[np.int64], float, int]:
    """The cheapest lattice route from state ``(sx, sy, sk)`` to cell ``(gx, gy)`` at any heading.

    Only cells inside the window of ``h`` (origin ``(x0, y0)``) are searched; the body is checked
    against the whole ``grid``. The start state is not checked (the robot is there already), and
    at the start cell the LETHAL cells in ``start_ignore`` (those the body overlaps where it
    stands) do not count: a robot touching a mark may turn away from it, but not into more.
    States farther than ``exact_within`` [cells] from the start are checked with the ``padded``
    body (the same outline grown by a margin, with as many vertices): the route ahead leaves
    room for control and localization to err, but the robot is not asked for room it has not
    got where it stands.

    Returns:
        ``(states, cost, expansions)``: states (N, 3) of ``(ix, iy, k)`` from start to goal, or
        (0, 3) if none within ``max_expansions``; the cost [cells].
    """
    hh, ww = h.shape
    n_states = hh * ww * HEADINGS
    g = np.full(n_states, np.inf, dtype=np.float32)
    parent = np.full(n_states, -1, dtype=np.int32)
    state = np.zeros(n_states, dtype=np.uint8)  # body check: unseen, free, blocked
    closed = np.zeros(n_states, dtype=np.bool_)
    world = np.empty_like(verts)
    reach = reach_of(padded, 0.0)
    near2 = exact_within * exact_within
    keys = np.empty(4096, dtype=np.float64)
    vals = np.empty(4096, dtype=np.int64)
    empty = np.zeros((0, 3), dtype=np.int64)
    if not (x0 <= sx < x0 + ww and y0 <= sy < y0 + hh):
        return empty, np.inf, 0
    start = ((sy - y0) * ww + (sx - x0)) * HEADINGS + sk
    g[start] = 0.0
    keys[0] = h[sy - y0, sx - x0]
    vals[0] = start
    n = 1
    expansions = 0
    goal_state = -1
    while n > 0:
        s = vals[0]
        _heap_pop(keys, vals, n)
        n -= 1
        if closed[s]:
            continue
        closed[s] = True
        expansions += 1
        k = s % HEADINGS
        cell = s // HEADINGS
        ly, lx = cell // ww, cell % ww
        ix, iy = lx + x0, ly + y0
        if ix == gx and iy == gy:
            goal_state = s
            break
        if expansions > max_expansions:
            break
        gs = float(g[s])
        at_start = ix == sx and iy == sy
        # Successors: forward along heading k, and turns to k - 1 and k + 1.
        for move in range(3):
            if move == 0:
                nk = k
                nx, ny = ix + MOVE_DX[k], iy + MOVE_DY[k]
            else:
                nk = (k + (1 if move == 1 else HEADINGS - 1)) % HEADINGS
                nx, ny = ix, iy
            lnx, lny = nx - x0, ny - y0
            if lnx < 0 or lny < 0 or lnx >= ww or lny >= hh:
                continue
            t = (lny * ww + lnx) * HEADINGS + nk
            if closed[t]:
                continue
            if not math.isfinite(h[lny, lnx]):
                continue
            if move == 0:
                if not _passable(grid, mult, nx, ny):
                    continue
                dx, dy = MOVE_DX[k], MOVE_DY[k]
                if dx != 0 and dy != 0:
                    # No corner cutting: the cells the centre line passes beside are passable.
                    if abs(dx) == 2:
                        sxn = 1 if dx > 0 else -1
                        if not (_passable(grid, mult, ix + sxn, iy)
                                and _passable(grid, mult, ix + sxn, iy + dy)):
                            continue
                    elif abs(dy) == 2:
                        syn = 1 if dy > 0 else -1
                        if not (_passable(grid, mult, ix, iy + syn)
                                and _passable(grid, mult, ix + dx, iy + syn)):
                            continue
                    else:
                        if not (_passable(grid, mult, ix + dx, iy)
                                and _passable(grid, mult, ix, iy + dy)):
                            continue
                step = math.sqrt(float(dx * dx + dy * dy)) * mult[grid[ny, nx]]
            else:
                d = ANGLES[nk] - ANGLES[k]
                while d > math.pi:
                    d -= 2.0 * math.pi
                while d < -math.pi:
                    d += 2.0 * math.pi
                step = turn_cost * abs(d)
            ignore = start_ignore if at_start and move != 0 else NO_CELLS
            body = _body_for(verts, padded, nx - sx, ny - sy, near2)
            if state[t] == _UNSEEN or (at_start and move != 0):
                free = _body_free(grid, near, res, body, reach, nx + 0.5, ny + 0.5,
                                  ANGLES[nk], world, ignore)
                if not (at_start and move != 0):
                    state[t] = _FREE if free else _BLOCKED
            else:
                free = state[t] == _FREE
            if not free:
                continue
            if move != 0 and not _turn_free(grid, near, res, body, reach, ix + 0.5, iy + 0.5,
                                            ANGLES[k], ANGLES[nk], rot_step, world, ignore):
                continue
            ng = gs + step
            if ng < g[t]:
                g[t] = ng
                parent[t] = s
                if n == keys.shape[0]:
                    keys, vals = _grown(keys, vals)
                _heap_push(keys, vals, n, ng + h[lny, lnx], t)
                n += 1
    if goal_state < 0:
        return empty, np.inf, expansions
    count = 1
    s = goal_state
    while parent[s] >= 0:
        s = parent[s]
        count += 1
    out = np.empty((count, 3), dtype=np.int64)
    s = goal_state
    for i in range(count - 1, -1, -1):
        cell = s // HEADINGS
        out[i, 0] = cell % ww + x0
        out[i, 1] = cell // ww + y0
        out[i, 2] = s % HEADINGS
        s = parent[s]
    return out, float(g[goal_state]), expansions


@numba.njit(cache=True, nogil=True)
def _segment(
    grid: npt.NDArray[np.uint8],
    mult: npt.NDArray[np.float64],
    near: npt.NDArray[np.bool_],
    res: float,
    verts: npt.NDArray[np.float64],
    reach: float,
    ax: float,
    ay: float,
    bx: float,
    by: float,
    world: npt.NDArray[np.float64],
) -> float:
    """Cost [cells] of the straight leg a -> b with the body facing along it; ``inf`` if the
    centre crosses an impassable cell or the body touches a LETHAL one (half-cell samples)."""
    dx, dy = bx - ax, by - ay
    length = math.sqrt(dx * dx + dy * dy)
    if length <= 0.0:
        return 0.0
    theta = math.atan2(dy, dx)
    n = max(int(math.ceil(length / 0.5)), 1)
    cost = 0.0
    for i in range(1, n + 1):
        x = ax + dx * i / n
        y = ay + dy * i / n
        ix, iy = int(math.floor(x)), int(math.floor(y))
        if not _passable(grid, mult, ix, iy):
            return np.inf
        if not _body_free(grid, near, res, verts, reach, x, y, theta, world, NO_CELLS):
            return np.inf
        cost += (length / n) * mult[grid[iy, ix]]
    return cost


@numba.njit(cache=True, nogil=True)
def shorten(
    grid: npt.NDArray[np.uint8],
    mult: npt.NDArray[np.float64],
    near: npt.NDArray[np.bool_],
    res: float,
    verts: npt.NDArray[np.float64],
    rot_step: float,
    states: npt.NDArray[np.int64],
    start_theta: float,
    max_span: int,
    padded: npt.NDArray[np.float64],
    exact_within: float,
) -> npt.NDArray[np.int64]:
    """Indices of the lattice states kept as vertices of the shortened route (module docstring).

    A leg from vertex ``i`` to state ``j`` replaces the states between them when the body stays
    free along it, the turn at ``i`` onto it is free (not checked at the start, where the robot
    already stands), and it costs no more than the lattice route between them. Legs from
    vertices farther than ``exact_within`` [cells] from the start are checked with the
    ``padded`` body, as the search checks its states.
    """
    n = states.shape[0]
    world = np.empty_like(verts)
    reach = reach_of(padded, 0.0)
    near2 = exact_within * exact_within
    # Lattice cost of the moves (turns left out) up to each state.
    along = np.zeros(n)
    for i in range(1, n):
        dx = states[i, 0] - states[i - 1, 0]
        dy = states[i, 1] - states[i - 1, 1]
        along[i] = along[i - 1] + math.sqrt(float(dx * dx + dy * dy)) * mult[
            grid[states[i, 1], states[i, 0]]]
    kept = np.empty(n, dtype=np.int64)
    count = 0
    i = 0
    heading = start_theta
    kept[count] = 0
    count += 1
    while i < n - 1:
        best = i + 1
        ax, ay = states[i, 0] + 0.5, states[i, 1] + 0.5
        body = _body_for(verts, padded, states[i, 0] - states[0, 0],
                         states[i, 1] - states[0, 1], near2)
        for j in range(i + 1, min(n, i + max_span + 1)):
            bx, by = states[j, 0] + 0.5, states[j, 1] + 0.5
            if bx == ax and by == ay:
                best = j
                continue
            cost = _segment(grid, mult, near, res, body, reach, ax, ay, bx, by, world)
            if cost > along[j] - along[i] + 1e-6:
                continue
            theta = math.atan2(by - ay, bx - ax)
            if i > 0 and not _turn_free(grid, near, res, body, reach, ax, ay, heading, theta,
                                        rot_step, world, NO_CELLS):
                continue
            best = j
        bx, by = states[best, 0] + 0.5, states[best, 1] + 0.5
        if bx != ax or by != ay:
            heading = math.atan2(by - ay, bx - ax)
        i = best
        kept[count] = i
        count += 1
    return kept[:count].copy()


def warm_up() -> None:
    """Compile the kernels on a tiny grid."""
    grid = np.zeros((12, 12), dtype=np.uint8)
    grid[5, 5] = 254
    mult = np.ones(256)
    mult[253:] = np.inf
    near = np.ones((12, 12), dtype=np.bool_)
    verts = np.array([[0.1, 0.08], [-0.1, 0.08], [-0.1, -0.08], [0.1, -0.08]])
    h = cost_to_go(grid, mult, 10, 10, 0, 0, 12, 12)
    states, _, _ = search(grid, mult, near, 0.05, verts, 0.1, 1.0, h, 0, 0, 1, 1, 0, 10, 10,
                          10_000, NO_CELLS, verts * 1.2, 4.0)
    shorten(grid, mult, near, 0.05, verts, 0.1, states, 0.0, 20, verts * 1.2, 4.0)
