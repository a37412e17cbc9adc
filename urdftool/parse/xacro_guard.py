"""Budgets of a xacro expansion: elements evaluated, CPU time, and expressions that amplify.

xacro runs in this process and evaluates ``${…}`` expressions with Python's ``eval``. A
description can therefore ask for unbounded work in a few characters: a macro that calls itself
twice, forty levels deep (2^40 elements), ``${9**9**9}`` (a number of 370 million digits), or
``${'x' * 10**10}`` (a 10 GB string). The guard bounds all three:

- every element xacro evaluates is counted, and the count and the CPU time spent are held to the
  ``xacro-elements`` and ``xacro-seconds`` budgets (:mod:`urdftool.budgets`); in the main thread
  of a POSIX process a CPU-time alarm also stops one expression that is slow without building
  anything large (a nested comprehension of 10^12 steps);
- an expression is compiled with its amplifiers routed through checks that refuse a result
  beyond a fixed size before computing it: ``**`` and ``<<`` on integers (at most
  :data:`MAX_INT_BITS` bits), ``*`` that repeats a string, list or tuple, ``range`` and the
  string methods that pad to a length (at most ten times ``xacro-elements`` items), and format
  widths written in the expression.

A refusal is a :class:`BudgetSpent`, which the expansion reports as one ``xacro-error`` naming
the budget. The check is of the result's size, not of the expression's shape, so every valid
xacro expression evaluates as before; ``tests/test_xacro_budgets.py`` holds both sides.
"""

from __future__ import annotations

import ast
import contextlib
import functools
import os
import re
import signal
import sys
import threading
import time
import types
from collections.abc import Iterator
from typing import Any

from urdftool.budgets import budget, how_to_raise

#: the largest integer an expression may build with ``**`` or ``<<`` or ``*`` (bits)
MAX_INT_BITS = 1 << 20

#: names the compiled expressions call; put in each evaluation's globals
_HELPERS = ("_urdftool_pow_", "_urdftool_mul_", "_urdftool_lshift_", "_urdftool_sized_")
#: string methods whose integer arguments are a length to pad or expand to
_PADDING = frozenset({"ljust", "rjust", "center", "zfill", "expandtabs"})
#: a width or precision of seven digits or more in a format string
_WIDE = re.compile(r"\d{7,}")


class BudgetSpent(Exception):
    """A xacro expansion stopped at one of its budgets."""

    def __init__(self, name: str, what: str) -> None:
        super().__init__(f"expansion stopped: {what}; {how_to_raise(name)}")
        self.budget = name


def _items_cap() -> int:
    return int(budget("xacro-elements")) * 10


def _pow(base: Any, exponent: Any) -> Any:
    if (_is_int(base) and _is_int(exponent) and exponent > 0 and abs(base) > 1
            and exponent * base.bit_length() > MAX_INT_BITS):
        raise BudgetSpent("xacro-elements", f"{base}**{exponent} has more than {MAX_INT_BITS} bits")
    return base**exponent


def _mul(left: Any, right: Any) -> Any:
    for seq, count in ((left, right), (right, left)):
        if isinstance(seq, (str, bytes, list, tuple)) and _is_int(count) and len(seq) * count > _items_cap():
            raise BudgetSpent("xacro-elements", f"repeating a {type(seq).__name__} of {len(seq)} items "
                              f"{count} times builds more than {_items_cap()} items")
    if _is_int(left) and _is_int(right) and left.bit_length() + right.bit_length() > MAX_INT_BITS:
        raise BudgetSpent("xacro-elements", f"a product of more than {MAX_INT_BITS} bits")
    return left * right


def _lshift(value: Any, places: Any) -> Any:
    if _is_int(value) and _is_int(places) and value and places + value.bit_length() > MAX_INT_BITS:
        raise BudgetSpent("xacro-elements", f"{value} << {places} has more than {MAX_INT_BITS} bits")
    return value << places


def _sized(function: Any, *args: Any, **kwargs: Any) -> Any:
    """``function(*args)`` for ``range`` and the padding methods, when no size given is beyond the
    cap (``range`` may be xacro's deprecation wrapper around the builtin: its arguments decide)."""
    cap = _items_cap()
    for value in (*args, *kwargs.values()):
        if _is_int(value) and abs(value) > cap:
            name = getattr(function, "__name__", "a call")
            raise BudgetSpent("xacro-elements", f"{name}() given {value}, more than {cap} items")
    return function(*args, **kwargs)


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


class _Amplifiers(ast.NodeTransformer):
    """Routes ``**``, ``*``, ``<<``, ``range(…)`` and the padding methods through the checks."""

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        helper = {ast.Pow: "_urdftool_pow_", ast.Mult: "_urdftool_mul_", ast.LShift: "_urdftool_lshift_"}.get(
            type(node.op))
        if helper is None:
            if isinstance(node.op, ast.Mod) and isinstance(node.left, ast.Constant):
                _check_format(node.left.value)
            return node
        return ast.Call(ast.Name(helper, ast.Load()), [node.left, node.right], [])

    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        func = node.func
        name = func.id if isinstance(func, ast.Name) else func.attr if isinstance(func, ast.Attribute) else ""
        if isinstance(func, ast.Attribute) and func.attr == "format" and isinstance(func.value, ast.Constant):
            _check_format(func.value.value)
        if name == "range" or (isinstance(func, ast.Attribute) and name in _PADDING):
            return ast.Call(ast.Name("_urdftool_sized_", ast.Load()), [func, *node.args], node.keywords)
        return node

    def visit_FormattedValue(self, node: ast.FormattedValue) -> ast.AST:
        self.generic_visit(node)
        if node.format_spec is not None:
            for part in ast.walk(node.format_spec):
                if isinstance(part, ast.Constant):
                    _check_format(part.value)
        return node


def _check_format(text: Any) -> None:
    if isinstance(text, str) and _WIDE.search(text):
        raise BudgetSpent("xacro-elements", f"a format width of seven digits or more in '{text[:40]}'")


@functools.lru_cache(maxsize=4096)
def _compiled(expression: str) -> types.CodeType:
    """*expression* compiled with its amplifiers routed through the checks, once per text: a
    macro's expressions are evaluated again at every call, and a code object is immutable."""
    parsed = ast.parse(expression, "<expression>", "eval")
    return compile(ast.fix_missing_locations(_Amplifiers().visit(parsed)), "<expression>", "eval")


def guarded_eval(refused: type[Exception], expression: str, symbols: Any, local: Any = None) -> Any:
    """xacro's ``safe_eval`` with the amplifiers checked: the same names refused (raising xacro's
    exception class *refused*), no builtins."""
    code = _compiled(expression.strip())
    invalid = [name for name in code.co_names if name.startswith("__")]
    if invalid:
        raise refused("Use of invalid name(s): ", ", ".join(invalid))
    symbols.update(__builtins__={})
    # dict's own setitem: xacro's symbol table reports redefinitions through its own
    for name, helper in zip(_HELPERS, (_pow, _mul, _lshift, _sized), strict=True):
        dict.__setitem__(symbols, name, helper)
    return eval(code, symbols, local)


@contextlib.contextmanager
def guarded(xacro: Any) -> Iterator[None]:
    """Count the elements *xacro* evaluates and its CPU time, and guard its expressions, for the
    duration of the block."""
    original_eval_all, original_eval = xacro.eval_all, xacro.safe_eval
    elements = int(budget("xacro-elements"))
    seconds = budget("xacro-seconds")
    start = time.process_time()
    evaluated = 0

    def eval_all(node: Any, macros: Any, symbols: Any) -> Any:
        nonlocal evaluated
        evaluated += 1
        if evaluated > elements:
            raise BudgetSpent("xacro-elements", f"more than {elements} elements evaluated")
        if not evaluated & 255 and time.process_time() - start > seconds:
            raise BudgetSpent("xacro-seconds", f"more than {seconds:g} s of CPU time")
        return original_eval_all(node, macros, symbols)

    xacro.eval_all, xacro.safe_eval = eval_all, functools.partial(guarded_eval, xacro.XacroException)
    try:
        with _cpu_alarm(seconds, expansion_code_folders(xacro)):
            yield
    finally:
        xacro.eval_all, xacro.safe_eval = original_eval_all, original_eval


#: after the first alarm, how often it rings again (s of CPU): an ``except Exception`` inside
#: xacro that swallows one alarm does not let the expansion run on unbounded
_ALARM_REPEAT = 0.5
#: how soon the alarm rings again when it found the process outside the expansion's code (s of CPU)
_ALARM_RETRY = 0.01


def expansion_code_folders(xacro: Any) -> tuple[str, ...]:
    """The folders of the code an expansion runs: xacro's and urdftool's."""
    return tuple(os.path.dirname(module.__file__ or "") + os.sep
                 for module in (xacro, sys.modules["urdftool"]))


def interrupts_safely(frame: types.FrameType | None, folders: tuple[str, ...]) -> bool:
    """Whether an exception raised in *frame* reaches the expansion: the frame runs an expression,
    or code of xacro or urdftool. Python runs a signal handler in whatever frame is current,
    which may be a garbage-collector callback, a finaliser or a weak-reference callback of
    another library; an exception raised there is printed as "Exception ignored" and lost."""
    if frame is None:
        return False
    filename = frame.f_code.co_filename
    return filename == "<expression>" or filename.startswith(folders)


@contextlib.contextmanager
def _cpu_alarm(seconds: float, folders: tuple[str, ...]) -> Iterator[None]:
    """Raise :class:`BudgetSpent` wherever the block is when it has used *seconds* of CPU time,
    inside one expression too. Python runs signal handlers in the main thread only, and Windows has
    no CPU-time timer: elsewhere the check between elements (:func:`guarded`) is the bound. When
    the alarm finds another library's code running (:func:`interrupts_safely`), it rings again
    after :data:`_ALARM_RETRY` instead of raising there."""
    if (not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGVTALRM) not in (signal.SIG_DFL, None)):
        yield  # (the last: a program that embeds urdftool uses this alarm itself; it is left alone)
        return
    armed = True

    def ring(signum: int, frame: types.FrameType | None) -> None:
        if not armed:  # a signal already on its way when the block ends is dropped
            return
        if not interrupts_safely(frame, folders):
            signal.setitimer(signal.ITIMER_VIRTUAL, _ALARM_RETRY, _ALARM_REPEAT)
            return
        raise BudgetSpent("xacro-seconds", f"more than {seconds:g} s of CPU time")

    previous = signal.signal(signal.SIGVTALRM, ring)
    signal.setitimer(signal.ITIMER_VIRTUAL, seconds, _ALARM_REPEAT)
    try:
        yield
    finally:
        armed = False
        signal.setitimer(signal.ITIMER_VIRTUAL, 0)
        signal.signal(signal.SIGVTALRM, signal.SIG_DFL if previous is None else previous)
