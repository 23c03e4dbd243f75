"""Compiled kernels: the simulator's per-step and per-beam arithmetic in machine code.

Every physics step runs the balance controller, and every LiDAR frame turns a few
hundred beams into readings and a few dozen IMU samples into estimates: many operations
on a few numbers each. As Python or as numpy calls each costs microseconds of
interpreter and call overhead for nanoseconds of arithmetic, and the physics steps in
between push the interpreter's and numpy's code out of the CPU's caches. :func:`kernel`
compiles such a function with numba into one call.

The options keep the arithmetic of the Python and numpy code the kernels replaced, to
the bit: no fast-math (no reordering, no fused multiply-adds), numpy's error model (a
division by zero gives ``inf`` or ``nan``, as numpy does, instead of raising). A kernel
writes its sums in the order numpy used (``np.einsum`` over rows of three adds the first
and the last product first). Compiled code is cached on disk (``__pycache__``), so a
process compiles a kernel only the first time it runs on a machine; with the environment
variable ``NUMBA_DISABLE_JIT=1`` the kernels run as plain Python (slowly), for debugging.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import numba

PACKAGE_DIR = Path(__file__).resolve().parent
FIRST_COMPILE_NOTICE = "compiling the simulator's kernels, once on this machine (about 15 s)"

F = TypeVar("F", bound=Callable[..., object])


def kernel(function: F) -> F:
    """``function`` compiled by numba with the simulator's options (see the module)."""
    return numba.njit(cache=True, nogil=True, error_model="numpy")(function)


def compiled_on_this_machine(package_dir: Path = PACKAGE_DIR) -> bool:
    """Whether the kernels were compiled here before: numba's cache index of the ray cast
    (the largest kernel) is beside its module. Where numba caches elsewhere
    (``NUMBA_CACHE_DIR``) this cannot tell, and says so (True: no notice)."""
    if numba.config.CACHE_DIR:
        return True
    return any((package_dir / "__pycache__").glob("ray_culling.*.nbi"))
