"""Pure-Python parts of the ffdaabb module: the checked array views and the small result types.

Imported by the extension (ffdaabb._ffdaabb) on first use; it imports nothing of the extension.
"""

from __future__ import annotations

import weakref
from typing import NamedTuple

import numpy as np

__all__ = ["StaleViewError", "View", "Mesh", "RayHit", "Contact", "ContactPair", "BodyContact"]


class StaleViewError(ReferenceError):
    """A view of a World's memory was used after the World's arrays were reallocated.

    World.vertices, particles, velocities, triangles and the all_* arrays view the world's memory
    without copying. Adding or removing a body, or restoring a state, moves that memory: views
    taken before then raise this error instead of reading freed memory. Take the view again, or
    keep a copy (``np.array(view)``) of what must outlive the change.
    """


class _Layout:
    """One arrangement of a World's arrays: valid until bodies come or go or a state is restored.

    Every view of it is tracked (weakly) so that, when it ends, each is detached: its shape
    becomes empty, so that even paths that bypass View's checks (the C API, memoryview) read
    nothing rather than freed memory.
    """

    __slots__ = ("valid", "_views", "_limit", "__weakref__")

    def __init__(self) -> None:
        self.valid = True
        self._views: list[weakref.ref] = []
        self._limit = 64

    def track(self, view: np.ndarray) -> None:
        self._views.append(weakref.ref(view))
        if len(self._views) > self._limit:
            self._views = [r for r in self._views if r() is not None]
            self._limit = max(64, 2 * len(self._views))

    def invalidate(self, detach) -> None:
        self.valid = False
        for ref in self._views:
            view = ref()
            if view is not None:
                detach(view)
        self._views = []


def _stale() -> StaleViewError:
    return StaleViewError(
        "this view of a World's arrays was taken before bodies were added or removed or a "
        "state was restored, which moved them; take it again (World.vertices, particles, "
        "velocities, triangles, all_vertices, all_particles, all_velocities)"
    )


def _plain(x):
    """x with every View in it (also inside tuples and lists) checked and seen as a plain array."""
    if isinstance(x, View):
        x._check()
        return x.view(np.ndarray)
    if isinstance(x, (tuple, list)):
        return type(x)(_plain(y) for y in x)
    return x


def _views_in(x, found: list) -> list:
    if isinstance(x, View):
        found.append(x)
    elif isinstance(x, (tuple, list)):
        for y in x:
            _views_in(y, found)
    return found


def _rewrap(result, views: list):
    """Results that share a view's memory stay views of its layout (checked and detached too)."""
    if isinstance(result, np.ndarray) and not isinstance(result, View):
        if not result.flags.owndata:
            for v in views:
                if v._layout is not None and np.may_share_memory(result, v):
                    out = result.view(View)
                    out._layout = v._layout
                    v._layout.track(out)
                    return out
        return result
    if isinstance(result, tuple):
        return tuple(_rewrap(r, views) for r in result)
    if isinstance(result, list):
        return [_rewrap(r, views) for r in result]
    return result


class View(np.ndarray):
    """A read-only NumPy array that views a World's memory without copying.

    It sees every later step() of the world (no copy is made). It is an ordinary ``ndarray`` for
    NumPy: indexing, slicing, ufuncs and NumPy functions all work, and slices of it are Views
    too. Once the world's arrays move (a body added or removed, a state restored), using it
    raises StaleViewError. ``np.asarray(view)`` and ``view.view(np.ndarray)`` give a plain array of
    the same memory that is no longer checked: copy (``np.array(view)``) what you keep.
    """

    _layout: _Layout | None = None

    def __array_finalize__(self, obj) -> None:
        layout = getattr(obj, "_layout", None)
        if layout is not None and not self.flags.owndata:
            self._layout = layout
            layout.track(self)
        else:
            self._layout = None

    @property
    def stale(self) -> bool:
        """True once the world's arrays have moved: the view can no longer be used."""
        return self._layout is not None and not self._layout.valid

    def _check(self) -> None:
        layout = self._layout
        if layout is not None and not layout.valid:
            raise _stale()

    def __getitem__(self, key):
        self._check()
        return super().__getitem__(key)

    def __setitem__(self, key, value):
        self._check()
        super().__setitem__(key, value)

    def __iter__(self):
        self._check()
        return super().__iter__()

    def __array__(self, dtype=None, *args, **kwargs):
        self._check()
        plain = self.view(np.ndarray)
        return plain if dtype is None else plain.astype(dtype, copy=False)

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        if "out" in kwargs:
            kwargs["out"] = _plain(tuple(kwargs["out"]))
        return getattr(ufunc, method)(*_plain(inputs), **kwargs)

    def __array_function__(self, func, types, args, kwargs):
        views = _views_in(args, [])
        _views_in(tuple(kwargs.values()), views)
        result = func(*_plain(args), **{k: _plain(v) for k, v in kwargs.items()})
        return _rewrap(result, views)

    def __repr__(self) -> str:
        if self.stale:
            return f"<stale ffdaabb.View of shape {self.shape}>"
        return repr(self.view(np.ndarray)).replace("array(", "View(", 1)

    def __str__(self) -> str:
        self._check()
        return str(self.view(np.ndarray))

    def __format__(self, spec: str) -> str:
        self._check()
        return format(self.view(np.ndarray), spec)

    def __reduce__(self):
        self._check()
        return np.array(self.view(np.ndarray)).__reduce__()

    def __reduce_ex__(self, protocol):
        self._check()
        return np.array(self.view(np.ndarray)).__reduce_ex__(protocol)

    def __copy__(self):
        return self.copy()

    def __deepcopy__(self, memo):
        return self.copy()

    def __bool__(self) -> bool:
        self._check()
        return bool(self.view(np.ndarray))

    def __float__(self) -> float:
        self._check()
        return float(self.view(np.ndarray))

    def __int__(self) -> int:
        self._check()
        return int(self.view(np.ndarray))

    def copy(self, order="C"):
        """A plain ndarray holding a copy of the view's values now."""
        self._check()
        return self.view(np.ndarray).copy(order)

    def astype(self, dtype, *args, **kwargs):
        self._check()
        return self.view(np.ndarray).astype(dtype, *args, **kwargs)

    def tolist(self):
        self._check()
        return self.view(np.ndarray).tolist()

    def tobytes(self, order="C"):
        self._check()
        return self.view(np.ndarray).tobytes(order)

    def item(self, *args):
        self._check()
        return self.view(np.ndarray).item(*args)


def _make_view(array: np.ndarray, layout: _Layout) -> View:
    view = array.view(View)
    view._layout = layout
    layout.track(view)
    return view


class Mesh(NamedTuple):
    """A triangle mesh as arrays: vertices float32 (V, 3), metres; triangles uint32 (T, 3)."""

    vertices: np.ndarray
    triangles: np.ndarray


class RayHit(NamedTuple):
    """Where a ray meets a body's deformed mesh (World.raycast)."""

    body: object  # BodyId
    triangle: int
    barycentric: np.ndarray
    distance: float
    point: np.ndarray
    normal: np.ndarray


class Contact(NamedTuple):
    """A contact of the last substep (World.contacts): body_b is None for the floor."""

    body_a: object
    body_b: object
    point: np.ndarray
    normal: np.ndarray
    depth: float
    impulse: float


class ContactPair(NamedTuple):
    """Two bodies (body_b None: the floor) that had contacts in the last step."""

    body_a: object
    body_b: object
    normal_impulse: float
    impulse: np.ndarray
    contact_count: int


class BodyContact(NamedTuple):
    """One of a body's partners in the last step (other None: the floor)."""

    other: object
    normal_impulse: float
    impulse: np.ndarray
    contact_count: int
