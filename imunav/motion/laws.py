"""Motion laws: strings like ``"10*sin(0.3*t)"`` parsed by a whitelist, never run as code.

A law is read by Python's own parser (:func:`ast.parse`, which only builds a syntax tree and
executes nothing) and the tree is then translated node by node into a SymPy expression.
Only these nodes are accepted:

- numbers (integers, decimals, scientific notation), the time ``t``, the constants ``pi``
  and ``E``;
- ``+ - * / **``, unary ``+``/``-`` and parentheses;
- calls of the smooth functions in :data:`FUNCTIONS` with positional arguments.

Everything else — attribute access, subscripts, names other than the above, strings,
lambdas, comparisons, keyword arguments, ``^`` — is refused with an :class:`ImunavError` that
names the law and the offending token. The functions are those that have exact derivatives
everywhere they are defined and lambdify to numpy; non-smooth ones (``Abs``, ``sign``,
``floor``, ``Heaviside``, ``Min``/``Max``, ``Mod``) are refused because the simulation needs
the first and second derivatives of every law.

Bounds keep any law cheap to parse: at most :data:`MAX_CHARS` characters,
:data:`MAX_NODES` syntax nodes and :data:`MAX_DEPTH` levels of nesting (its derivatives are
built recursively); every constant sub-expression must stay within
``±MAX_MAGNITUDE`` and a constant exponent within ``±MAX_EXPONENT`` (so ``9**9**9`` is refused
instead of computing a 370-million-digit integer). A law whose constants are complex
(``sqrt(-1)``, ``log(-2)``, ``asin(2)``) is refused; a law that becomes complex or infinite only
at some times is caught when it is evaluated (see :func:`evaluate`).

SymPy expressions given directly (Python API) pass the same whitelist of node types.

May import: ``imunav.core``.
"""

from __future__ import annotations

import ast
import math
import numbers

import numpy as np
import sympy as sp

from imunav.core.validation import ImunavError

#: The time symbol of every law.
T = sp.Symbol("t", real=True)

MAX_CHARS = 2000
MAX_NODES = 500
MAX_DEPTH = 30
MAX_EXPONENT = 1000
MAX_MAGNITUDE = 1e300

#: name → (SymPy function, number of arguments). All smooth where defined; all lambdify to numpy.
FUNCTIONS: dict[str, tuple[type, int]] = {
    "sin": (sp.sin, 1), "cos": (sp.cos, 1), "tan": (sp.tan, 1),
    "asin": (sp.asin, 1), "acos": (sp.acos, 1), "atan": (sp.atan, 1), "atan2": (sp.atan2, 2),
    "sinh": (sp.sinh, 1), "cosh": (sp.cosh, 1), "tanh": (sp.tanh, 1),
    "asinh": (sp.asinh, 1), "acosh": (sp.acosh, 1), "atanh": (sp.atanh, 1),
    "exp": (sp.exp, 1), "log": (sp.log, 1), "sqrt": (sp.sqrt, 1),
}
#: name → SymPy constant.
CONSTANTS = {"pi": sp.pi, "E": sp.E}

_OPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_NOT_SMOOTH = {"Abs", "abs", "sign", "floor", "ceiling", "ceil", "Heaviside", "Min", "Max",
               "min", "max", "Mod", "mod", "Piecewise", "round"}
# sqrt is not a class (it builds a Pow); the others are SymPy function classes.
_ALLOWED_FUNC_CLASSES = tuple(f for f, _ in FUNCTIONS.values() if isinstance(f, type))


def _what(node: ast.AST, src: str) -> str:
    """The source text of ``node`` (for error messages), shortened."""
    seg = ast.get_source_segment(src, node) or type(node).__name__
    return seg if len(seg) <= 40 else seg[:37] + "..."


class _Builder:
    def __init__(self, name: str, src: str):
        self.name, self.src = name, src

    def fail(self, msg: str):
        src = self.src if len(self.src) <= 60 else self.src[:57] + "..."
        raise ImunavError(f"motion law {self.name!r} = {src!r}: {msg}")

    def build(self, node: ast.AST) -> sp.Expr:
        if isinstance(node, ast.Expression):
            return self.build(node.body)
        if isinstance(node, ast.Constant):
            v = node.value
            if isinstance(v, bool) or not isinstance(v, int | float):
                self.fail(f"{_what(node, self.src)!r} is not a number (only numbers, t, pi, E, "
                          "arithmetic and the listed functions are allowed)")
            if isinstance(v, float) and not math.isfinite(v):
                self.fail(f"the number {_what(node, self.src)} is not finite")
            return self.constant(sp.Integer(v) if isinstance(v, int) else sp.Float(v), node)
        if isinstance(node, ast.Name):
            if node.id == "t":
                return T
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            hint = " (a function name needs an argument)" if node.id in FUNCTIONS else ""
            self.fail(f"unknown name {node.id!r}{hint}; only 't' (time, s) and the constants "
                      f"{', '.join(CONSTANTS)} are allowed")
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.UAdd | ast.USub):
            e = self.build(node.operand)
            return self.constant(-e, node) if isinstance(node.op, ast.USub) else e
        if isinstance(node, ast.BinOp):
            if isinstance(node.op, ast.BitXor):
                self.fail("'^' is not a power here; write powers as '**'")
            if type(node.op) not in _OPS:
                self.fail(f"operator in {_what(node, self.src)!r} is not allowed; use + - * / **")
            a, b = self.build(node.left), self.build(node.right)
            if isinstance(node.op, ast.Pow):
                if not b.has(T):
                    eb = float(b)
                    if abs(eb) > MAX_EXPONENT:
                        self.fail(f"exponent {_what(node.right, self.src)} exceeds the limit "
                                  f"±{MAX_EXPONENT}")
                if not a.has(T) and b.has(T) and float(a) < 0:
                    self.fail(f"{_what(node, self.src)!r} is complex for non-integer t (negative "
                              "base); laws must be real")
                if not a.has(T) and not b.has(T):
                    ea, eb = float(a), float(b)
                    if ea != 0 and eb * math.log10(abs(ea)) > math.log10(MAX_MAGNITUDE):
                        self.fail(f"{_what(node, self.src)!r} exceeds {MAX_MAGNITUDE:g}")
                    if ea == 0 and eb < 0:
                        self.fail(f"{_what(node, self.src)!r} divides by zero")
                return self.constant(a ** b, node)
            if isinstance(node.op, ast.Div):
                if not b.has(T) and b == 0:
                    self.fail(f"{_what(node, self.src)!r} divides by zero")
                return self.constant(a / b, node)
            return self.constant({ast.Add: sp.Add, ast.Sub: lambda x, y: x - y,
                                  ast.Mult: sp.Mul}[type(node.op)](a, b), node)
        if isinstance(node, ast.Call):
            f = node.func
            if not isinstance(f, ast.Name):
                self.fail(f"{_what(f, self.src)!r} is not a function name")
            if f.id not in FUNCTIONS:
                why = (" (not smooth: the simulation needs exact first and second derivatives)"
                       if f.id in _NOT_SMOOTH else "")
                self.fail(f"function {f.id!r} is not allowed{why}; allowed: "
                          f"{', '.join(FUNCTIONS)}")
            if node.keywords:
                self.fail(f"{f.id}() takes no keyword arguments")
            func, arity = FUNCTIONS[f.id]
            if len(node.args) != arity or any(isinstance(a, ast.Starred) for a in node.args):
                self.fail(f"{f.id}() takes {arity} argument{'s' if arity > 1 else ''}, got "
                          f"{len(node.args)}")
            return self.constant(func(*(self.build(a) for a in node.args)), node)
        self.fail(f"{_what(node, self.src)!r} is not allowed (only numbers, t, pi, E, + - * / **, "
                  "parentheses and the listed functions)")

    def constant(self, e: sp.Expr, node: ast.AST) -> sp.Expr:
        """Check a constant (t-free) result: finite, real and of bounded magnitude."""
        if e.has(T):
            return e
        if e.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
            self.fail(f"{_what(node, self.src)!r} is not finite")
        if e.has(sp.I) or e.is_real is False:
            self.fail(f"{_what(node, self.src)!r} is complex; laws must be real")
        try:
            v = complex(e)
        except (TypeError, ValueError):
            return e
        if v.imag != 0:
            self.fail(f"{_what(node, self.src)!r} is complex; laws must be real")
        if not math.isfinite(v.real) or abs(v.real) > MAX_MAGNITUDE:
            self.fail(f"{_what(node, self.src)!r} exceeds {MAX_MAGNITUDE:g}")
        return e


def parse_law(expr: str | sp.Expr | numbers.Real, name: str) -> sp.Expr:
    """One motion law as a SymPy expression in :data:`T`.

    Parameters
    ----------
    expr : str, number or sympy.Expr
        A string such as ``"2*sin(t) + 0.1*t**2"`` (see the module docstring for what is
        allowed), a real number, or a SymPy expression built from the same pieces.
    name : str
        The law's name (``"x"``, ``"yaw"``, …), used in error messages.

    Returns
    -------
    sympy.Expr
        The law in the real symbol :data:`T` (a number gives a constant: an Integer for a
        whole number below 2**53, else a Float).

    Raises
    ------
    ImunavError
        Naming the law and the offending token: for a bool or another type, an empty string,
        one longer than :data:`MAX_CHARS` characters or of more than :data:`MAX_NODES` syntax
        nodes, a syntax error (with its column), a name, operator or function outside the
        whitelist (a non-smooth one says so), a constant that is complex, not finite, beyond
        ``±MAX_MAGNITUDE`` or with an exponent beyond ``±MAX_EXPONENT``, or a division by zero.

    Examples
    --------
    >>> parse_law("10*sin(0.3*t)", "x")
    10*sin(0.3*t)
    >>> parse_law("abs(t)", "x")                     # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    imunav.core.validation.ImunavError: motion law 'x' = 'abs(t)': function 'abs' is not allowed ...
    """
    if isinstance(expr, bool):
        raise ImunavError(f"motion law {name!r} must be a string, number or SymPy expression, "
                          f"got {expr!r}")
    if isinstance(expr, numbers.Real):
        v = float(expr)
        if not math.isfinite(v) or abs(v) > MAX_MAGNITUDE:
            raise ImunavError(f"motion law {name!r} = {expr!r} is not a finite number")
        return sp.Integer(int(v)) if v.is_integer() and abs(v) < 2**53 else sp.Float(v)
    if isinstance(expr, sp.Basic):
        return check_expression(expr, name)
    if not isinstance(expr, str):
        raise ImunavError(f"motion law {name!r} must be a string, number or SymPy expression, "
                          f"got {type(expr).__name__}")
    src = expr.strip()
    if not src:
        raise ImunavError(f"motion law {name!r} is an empty string")
    if len(src) > MAX_CHARS:
        raise ImunavError(f"motion law {name!r} is {len(src)} characters long; the limit is "
                          f"{MAX_CHARS}")
    try:
        tree = ast.parse(src, mode="eval")
    except SyntaxError as exc:
        where = f" at column {exc.offset}" if exc.offset else ""
        raise ImunavError(f"motion law {name!r} = {_short(src)!r} cannot be parsed{where}: "
                          f"{exc.msg}") from None
    except (ValueError, RecursionError, MemoryError):
        raise ImunavError(f"motion law {name!r} = {_short(src)!r} cannot be parsed") from None
    n = sum(1 for _ in ast.walk(tree))
    if n > MAX_NODES:
        raise ImunavError(f"motion law {name!r} has {n} syntax nodes; the limit is {MAX_NODES}")
    depth = _depth(tree)
    if depth > MAX_DEPTH:
        raise ImunavError(f"motion law {name!r} = {_short(src)!r} nests functions and powers "
                          f"{depth} deep; the limit is {MAX_DEPTH}")
    e = _Builder(name, src).build(tree)
    depth = _expression_depth(e)              # divisions nest too, as powers of -1
    if depth > MAX_DEPTH:
        raise ImunavError(f"motion law {name!r} = {_short(src)!r} nests functions and powers "
                          f"{depth} deep; the limit is {MAX_DEPTH}")
    return e


def _depth(tree: ast.AST) -> int:
    """The nesting of calls and powers in ``tree`` (sums and products are flat in SymPy;
    iteratively: a deep tree is what is being checked)."""
    deepest, stack = 0, [(tree, 0)]
    while stack:
        node, d = stack.pop()
        d += isinstance(node, ast.Call) or (isinstance(node, ast.BinOp)
                                            and isinstance(node.op, ast.Pow))
        deepest = max(deepest, d)
        stack.extend((child, d) for child in ast.iter_child_nodes(node))
    return deepest


def _expression_depth(e: sp.Basic) -> int:
    """The nesting of functions and powers in a SymPy expression (iteratively)."""
    deepest, stack = 0, [(e, 0)]
    while stack:
        node, d = stack.pop()
        d += isinstance(node, sp.Function | sp.Pow)
        deepest = max(deepest, d)
        stack.extend((arg, d) for arg in node.args)
    return deepest


def _short(src: str) -> str:
    return src if len(src) <= 60 else src[:57] + "..."


def check_expression(e: sp.Basic, name: str) -> sp.Expr:
    """Apply the whitelist to a SymPy expression built in Python.

    A user's own ``Symbol("t")`` (with or without assumptions) is taken as :data:`T`.

    Parameters
    ----------
    e : sympy.Basic
        The expression.
    name : str
        The law's name, used in error messages.

    Returns
    -------
    sympy.Expr
        ``e`` with its ``t`` replaced by :data:`T`.

    Raises
    ------
    ImunavError
        If ``e`` is not a scalar expression, has more than :data:`MAX_NODES` operations, uses
        a symbol other than ``t``, the imaginary unit or a function outside :data:`FUNCTIONS`,
        or is not finite.
    """
    if not isinstance(e, sp.Expr):
        raise ImunavError(f"motion law {name!r} is not a scalar expression")
    e = e.subs({s: T for s in e.free_symbols if getattr(s, "name", None) == "t"})
    if sp.count_ops(e, visual=False) > MAX_NODES:
        raise ImunavError(f"motion law {name!r} has more than {MAX_NODES} operations")
    depth = _expression_depth(e)
    if depth > MAX_DEPTH:
        raise ImunavError(f"motion law {name!r} nests functions and powers {depth} deep; the "
                          f"limit is {MAX_DEPTH}")
    for node in sp.preorder_traversal(e):
        if isinstance(node, sp.Symbol):
            if node != T:
                raise ImunavError(f"motion law {name!r} = {str(e)!r} uses symbol {node.name!r}; "
                                  "only 't' (time, s) is allowed")
        elif isinstance(node, sp.Number | sp.NumberSymbol | sp.Add | sp.Mul | sp.Pow):
            pass
        elif isinstance(node, _ALLOWED_FUNC_CLASSES):
            pass
        elif node is sp.I or isinstance(node, sp.core.numbers.ImaginaryUnit):
            raise ImunavError(f"motion law {name!r} = {str(e)!r} is complex; laws must be real")
        else:
            fname = getattr(getattr(node, "func", None), "__name__", type(node).__name__)
            raise ImunavError(f"motion law {name!r} = {str(e)!r} uses {fname!r}, which is not "
                              f"allowed; allowed functions: {', '.join(FUNCTIONS)}")
    if e.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise ImunavError(f"motion law {name!r} = {str(e)!r} is not finite")
    return e


def lambdify(expr: sp.Expr):
    """A numpy function ``f(t) → array of t's shape`` for a checked law (or a derivative).

    Numeric warnings are silenced here; the caller checks the result (:func:`evaluate`).

    Parameters
    ----------
    expr : sympy.Expr
        A law in :data:`T` that passed the whitelist (or one of its derivatives).

    Returns
    -------
    callable
        ``f(t)`` for an ndarray ``t`` of times (s); a constant law gives a full array of
        ``t``'s shape. The values may be complex, infinite or NaN: pass them through
        :func:`evaluate`.
    """
    f = sp.lambdify(T, expr, modules="numpy", cse=True)
    constant = not expr.has(T)

    def call(t: np.ndarray) -> np.ndarray:
        with np.errstate(all="ignore"):
            v = f(t)
        if constant:
            return np.full(np.shape(t), float(v))
        return np.asarray(v)

    return call


def evaluate(f, t: np.ndarray, what: str) -> np.ndarray:
    """``f(t)`` as a finite float64 array, checked.

    Parameters
    ----------
    f : callable
        A function from :func:`lambdify`.
    t : ndarray
        Times (s), any shape.
    what : str
        What ``f`` is, for the error message (``"position law x = '…'"``).

    Returns
    -------
    ndarray of float64
        ``f(t)``, of ``t``'s shape (a complex value with zero imaginary part is taken as real).

    Raises
    ------
    ImunavError
        Naming ``what`` and the first time at which the value is complex, infinite or NaN.

    Examples
    --------
    >>> import numpy as np
    >>> f = lambdify(parse_law("log(t)", "x"))
    >>> evaluate(f, np.array([1.0, 0.0]), "x = log(t)")
    Traceback (most recent call last):
    ...
    imunav.core.validation.ImunavError: x = log(t) is not finite (complex, infinite or NaN) at t = 0 s
    """
    v = f(t)
    if np.iscomplexobj(v):
        bad = np.nonzero(np.imag(v) != 0)[0] if v.ndim else np.array([0])
        if bad.size:
            tt = np.ravel(t)[bad[0]] if np.ndim(t) else float(t)
            raise ImunavError(f"{what} is complex at t = {float(tt):.6g} s")
        v = np.real(v)
    v = np.asarray(v, dtype=np.float64)
    if v.shape != np.shape(t):
        v = np.broadcast_to(v, np.shape(t)).copy()
    ok = np.isfinite(v)
    if not ok.all():
        i = int(np.argmin(ok.ravel()))
        tt = float(np.ravel(t)[i])
        raise ImunavError(f"{what} is not finite (complex, infinite or NaN) at t = {tt:.6g} s")
    return v
