"""ln x and x^(1/3) as straight-line arithmetic, so that loops calling them vectorise, and
``like``, which writes a literal in the float type of a value so that the element arithmetic
compiles unchanged in single or double precision.

Numba's ``np.log`` and ``np.cbrt`` are calls into the C library, which LLVM cannot vectorise
without a vector math library; these versions split x into exponent and mantissa with bit
operations (``float_bits``, ``bits_float``: LLVM bitcasts) and finish with polynomials and
iterations that are accurate to a unit or two in the last place (tests/unit/elements).
A float32 argument is computed in float32 (``log32``, ``cbrt32``): its vector holds twice the
lanes of a double one, and the float32 loops of the element kernel call both once per element.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

import numba as nb
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from batball.numerics import FASTMATH

_MANTISSA = np.uint64(0x000FFFFFFFFFFFFF)
_ONE_BITS = np.uint64(0x3FF0000000000000)  # bits of 1.0
_LOW_32 = np.uint64(0xFFFFFFFF)
_SHIFT_32, _SHIFT_52 = np.uint64(32), np.uint64(52)
_TWO_52_BITS = np.uint64(0x4330000000000000)  # bits of 2^52
_TWO_84_BITS = np.uint64(0x4530000000000000)  # bits of 2^84
_IMPLICIT_ONE = np.uint64(0x0010000000000000)  # the hidden bit of a normal float64
_BIAS_52 = np.uint64(1075)  # exponent bias + 52: the biased exponent of an integer's unit 1
_TWO_52 = 4503599627370496.0
_TWO_84_PLUS_52 = 19342813118337666422669312.0  # 2^84 + 2^52, exact
_SMALLEST_NORMAL = 2.2250738585072014e-308
_TWO_54 = 18014398509481984.0  # scales subnormals up to normal numbers
_SQRT2 = 1.4142135623730951
_LN2_HI = 6.93147180369123816490e-01  # ln 2 split so that k ln2_hi is exact (fdlibm)
_LN2_LO = 1.90821492927058770002e-10
# fdlibm e_log.c: minimax coefficients of (ln(1+f) - f + f^2/2) in s = f / (2 + f)
_LG1, _LG2 = 6.666666666666735130e-01, 3.999999999940941908e-01
_LG3, _LG4 = 2.857142874366239149e-01, 2.222219843214978396e-01
_LG5, _LG6 = 1.818357216161805012e-01, 1.531383769920937332e-01
_LG7 = 1.479819860511658591e-01
# bits(m^(-1/3)) ~ this - bits(m) / 3 (a first guess within 3.5 %)
_INVERSE_CBRT_MAGIC = np.uint64(0x553EF0FE047D3C00)

# float32: fdlibm's e_logf.c split of ln 2 (k ln2_hi exact for |k| < 128) and its minimax
# coefficients of (ln(1+f) - f + f^2/2) in s = f / (2 + f)
# (float32 values, typed as floats for mypy)
_LN2_HI_32 = cast("float", np.float32(float.fromhex("0x1.62e300p-1")))
_LN2_LO_32 = cast("float", np.float32(float.fromhex("0x1.2fefa2p-17")))
_LG1_32 = np.float32(float.fromhex("0xaaaaaa.0p-24"))
_LG2_32 = np.float32(float.fromhex("0xccce13.0p-25"))
_LG3_32 = np.float32(float.fromhex("0x91e9ee.0p-25"))
_LG4_32 = np.float32(float.fromhex("0xf89e26.0p-26"))
_SMALLEST_NORMAL_32 = np.float32(np.finfo(np.float32).smallest_normal)
_SQRT2_32 = np.float32(_SQRT2)
_TWO_24_32 = np.float32(2.0**24)  # scales float32 subnormals up to normal numbers
_INF_32 = np.float32(np.inf)
# bits(m^(-1/3)) ~ this - bits(m) / 3 for float32 m in [1, 8) (a first guess within 3.5 %)
_INVERSE_CBRT_MAGIC_32 = 0x54A23300


@intrinsic
def _float_bits(typingctx, x):
    """The IEEE-754 bits of a float64, as a uint64."""
    if x != types.float64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return types.uint64(types.float64), codegen


@intrinsic
def _bits_float(typingctx, bits):
    """The float64 with the given IEEE-754 bits (a uint64)."""
    if bits != types.uint64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(types.uint64), codegen


#: Typed views of the intrinsics for mypy (the same objects for Numba).
float_bits = cast("Callable[[float], np.uint64]", _float_bits)
bits_float = cast("Callable[[np.uint64], float]", _bits_float)


# The float32 bit work as LLVM's own 32-bit integer operations, in intrinsics: Numba widens
# arithmetic on 32-bit integers to 64 bits, which would halve the float32 loops' vector width.
_I32 = ir.IntType(32)


def _float32_map(bit_work: Callable[[ir.IRBuilder, ir.Value], ir.Value]):  # noqa: ANN202
    """An intrinsic float32 -> float32 that applies ``bit_work`` to the argument's bits (i32)."""

    @intrinsic
    def _map(typingctx, x):  # noqa: ANN001, ANN202
        if x != types.float32:
            return None

        def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
            bits = builder.bitcast(args[0], _I32)
            return builder.bitcast(bit_work(builder, bits), ir.FloatType())

        return types.float32(types.float32), codegen

    return cast("Callable[[float], float]", _map)


#: The biased exponent of a positive float32, as a float32 (exact).
_exponent32 = _float32_map(
    lambda b, bits: b.bitcast(b.uitofp(b.lshr(bits, _I32(23)), ir.FloatType()), _I32)
)
#: The significand of a finite float32 as a number in [1, 2).
_significand32 = _float32_map(
    lambda b, bits: b.or_(b.and_(bits, _I32(0x007FFFFF)), _I32(0x3F800000))
)
#: 2^k for an integer-valued float32 k in [-126, 127].
_power_of_two32 = _float32_map(
    lambda b, bits: b.shl(
        b.add(b.fptosi(b.bitcast(bits, ir.FloatType()), _I32), _I32(127)), _I32(23)
    )
)
#: A first guess of m^(-1/3) for a float32 m in [1, 8), within 3.5 %.
_inverse_cbrt_guess32 = _float32_map(
    lambda b, bits: b.sub(_I32(_INVERSE_CBRT_MAGIC_32), b.udiv(bits, _I32(3)))
)


@intrinsic
def _is_single(typingctx, x):  # noqa: ANN001, ANN202
    """True for a float32 ``x``, False for a float64: a constant, so LLVM keeps one branch."""
    if not isinstance(x, types.Float):
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        return context.get_constant(types.boolean, signature.args[0] == types.float32)

    return types.boolean(x), codegen


is_single = cast("Callable[[float], bool]", _is_single)
#: np.float32 as a conversion of one float (typed for mypy).
_single = cast("Callable[[float], float]", np.float32)


@intrinsic
def _like(typingctx, x, value):  # noqa: ANN001, ANN202
    """``value`` converted to the float type of ``x``: an LLVM cast (a constant folds)."""
    if not isinstance(x, types.Float) or not isinstance(types.unliteral(value), types.Number):
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        return context.cast(builder, args[1], signature.args[1], signature.return_type)

    return x(x, types.unliteral(value)), codegen


#: ``like(x, value)``: ``value`` in the float type of ``x`` (float32 or float64), inside Numba
#: code. Numba types a Python float literal as float64 and float32 op float64 as float64, so a
#: literal in single-precision arithmetic would promote the whole expression; written
#: ``like(x, 0.5)`` it stays single. An intrinsic, so it is a cast in the caller's own IR: an
#: overload was either a call LLVM did not inline (the element loop then did not vectorise) or,
#: with ``inline="always"``, inlined at Numba's IR level, which gave the foam kernel a zero
#: element volume in a fresh cache.
like = cast("Callable[[float, float], float]", _like)


def shuffle_mask(indices: list[int]) -> ir.Constant:
    """A constant LLVM shuffle mask."""
    return ir.Constant(ir.VectorType(_I32, len(indices)), [_I32(i) for i in indices])


def component_rows(
    builder: ir.IRBuilder, data: ir.Value, first: ir.Value, count: int
) -> list[ir.Value]:
    """LLVM IR: the 3 component rows (<count x double> each) of ``count`` consecutive 3-vectors
    from flat offset ``first`` of ``data`` (a double pointer): one load of 3 count doubles,
    split by shuffles."""
    span = ir.VectorType(ir.DoubleType(), 3 * count)
    values = builder.load(builder.bitcast(builder.gep(data, [first]), span.as_pointer()), align=8)
    return [builder.shuffle_vector(values, values, shuffle_mask(list(range(i, 3 * count, 3))))
            for i in range(3)]  # fmt: skip


def _joined(builder: ir.IRBuilder, vectors: list[ir.Value]) -> ir.Value:
    """LLVM IR: equal vectors concatenated in order, padded with undefined ones to a power of
    two (a tree of shuffles)."""
    level = list(vectors)
    while len(level) & (len(level) - 1):
        level.append(ir.Constant(vectors[0].type, ir.Undefined))
    while len(level) > 1:
        whole = shuffle_mask(list(range(2 * level[0].type.count)))
        level = [builder.shuffle_vector(level[i], level[i + 1], whole)
                 for i in range(0, len(level), 2)]  # fmt: skip
    return level[0]


def _joined_pairs(builder: ir.IRBuilder, bases: list[ir.Value], at: int) -> ir.Value:
    """The pairs of doubles at ``base + at`` of each base, concatenated in order into one
    <2 L x double> (a tree of shuffles, which LLVM lowers to lane inserts)."""
    pair = ir.VectorType(ir.DoubleType(), 2)
    offset = ir.IntType(64)(at)
    pairs = [builder.load(builder.bitcast(builder.gep(b, [offset]), pair.as_pointer()), align=8)
             for b in bases]  # fmt: skip
    return _joined(builder, pairs)  # (c_at, c_at+1) of vector 0, then of vector 1...


def transposed_lanes(
    builder: ir.IRBuilder, data: ir.Value, offsets: ir.Value, count: int
) -> list[ir.Value]:
    """LLVM IR for components 0..count-1 of L short vectors of doubles, the k-th at
    ``data + offsets[k]`` (``offsets`` an L-tuple, L a power of two): ``count`` rows, each an
    <L x double> of one component across the vectors. Each vector's components are loaded in
    pairs and the pairs interleaved by shuffles, which LLVM lowers to unpack and lane-insert
    instructions: half the loads of one value at a time. An odd last component is inserted
    value by value. (Taking it from the odd lanes of the pairs (c_count-2, c_count-1) instead
    made an 8-lane gather 6 % faster on a Sapphire Rapids Xeon but the 4-lane MITC4 corner
    gather a third slower; the callers now use 4 lanes.)"""
    lanes = len(offsets.type.elements)
    bases = [builder.gep(data, [builder.extract_value(offsets, k)]) for k in range(lanes)]
    evens = shuffle_mask(list(range(0, 2 * lanes, 2)))
    odds = shuffle_mask(list(range(1, 2 * lanes, 2)))
    rows = []
    for j in range(count // 2):
        both = _joined_pairs(builder, bases, 2 * j)
        rows.append(builder.shuffle_vector(both, both, evens))
        rows.append(builder.shuffle_vector(both, both, odds))
    if count % 2:
        row = ir.Constant(ir.VectorType(ir.DoubleType(), lanes), ir.Undefined)
        for k, b in enumerate(bases):
            value = builder.load(builder.gep(b, [ir.IntType(64)(count - 1)]), align=8)
            row = builder.insert_element(row, value, _I32(k))
        rows.append(row)
    return rows


@intrinsic
def _gather_columns(typingctx, w, index, stride, flat, offsets, count):  # noqa: ANN001, ANN202
    """``w[index + c stride + k] = flat[offsets[k] + c]`` for c < count and each lane k of
    ``offsets`` (a tuple of uint64; 2, 4 or 8 lanes) in float64 arrays: a work array's columns
    k of ``count`` rows from vectors of a flat nodal array, through :func:`transposed_lanes`
    (``count`` a compile-time constant)."""
    double = types.Array(types.float64, 1, "C")
    if (
        w != double
        or flat != double
        or index != types.uint64
        or stride != types.uint64
        or not isinstance(offsets, types.UniTuple)
        or offsets.dtype != types.uint64
        or offsets.count not in (2, 4, 8)
        or not isinstance(count, types.IntegerLiteral)
    ):
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        target = context.make_array(signature.args[0])(context, builder, value=args[0]).data
        data = context.make_array(signature.args[3])(context, builder, value=args[3]).data
        rows = transposed_lanes(builder, data, args[4], count.literal_value)
        for c, row in enumerate(rows):
            at = builder.add(args[1], builder.mul(args[2], ir.IntType(64)(c)))
            pointer = builder.bitcast(builder.gep(target, [at]), row.type.as_pointer())
            builder.store(row, pointer, align=8)
        return context.get_dummy_value()

    return types.none(w, index, stride, flat, offsets, count), codegen


#: Typed view of the intrinsic for mypy (the same object for Numba).
gather_columns = cast(
    "Callable[[np.ndarray, np.uint64, np.uint64, np.ndarray, tuple, int], None]", _gather_columns
)


@intrinsic
def _interleave_rows(typingctx, w, rows, target, lanes):  # noqa: ANN001, ANN202
    """``w[target + F c + k] = w[rows[k] + c]`` for c < lanes and each of the F offsets of
    ``rows`` (a tuple of uint64) in a float64 array: ``lanes`` columns of F rows of a work array
    as ``lanes`` records of F consecutive values, the reverse of :func:`gather_columns`. Each
    row is loaded as one vector and the records stored as one, interleaved by a shuffle, which
    LLVM lowers to unpack and permute instructions (``lanes`` a compile-time constant; the
    rows and the records must not overlap)."""
    double = types.Array(types.float64, 1, "C")
    if (
        w != double
        or not isinstance(rows, types.UniTuple)
        or rows.dtype != types.uint64
        or target != types.uint64
        or not isinstance(lanes, types.IntegerLiteral)
    ):
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        data = context.make_array(signature.args[0])(context, builder, value=args[0]).data
        n_rows, n_lanes = signature.args[1].count, lanes.literal_value
        row_type = ir.VectorType(ir.DoubleType(), n_lanes)
        loaded = []
        for k in range(n_rows):
            at = builder.gep(data, [builder.extract_value(args[1], k)])
            loaded.append(builder.load(builder.bitcast(at, row_type.as_pointer()), align=8))
        joined = _joined(builder, loaded)
        order = [k * n_lanes + c for c in range(n_lanes) for k in range(n_rows)]
        records = builder.shuffle_vector(joined, joined, shuffle_mask(order))
        pointer = builder.bitcast(builder.gep(data, [args[2]]), records.type.as_pointer())
        builder.store(records, pointer, align=8)
        return context.get_dummy_value()

    return types.none(w, rows, target, lanes), codegen


#: Typed view of the intrinsic for mypy (the same object for Numba).
interleave_rows = cast("Callable[[np.ndarray, tuple, np.uint64, int], None]", _interleave_rows)


@intrinsic
def _subtract_record(typingctx, flat, into, w, at, keep):  # noqa: ANN001, ANN202
    """``flat[into + k] = (flat[into + k] if keep else 0) - w[at + k]`` for k < 6 (float64
    arrays, unsigned offsets) as two vector loads, subtractions and stores (4 + 2 values)."""
    double = types.Array(types.float64, 1, "C")
    if flat != double or w != double or into != types.uint64 or at != types.uint64 \
            or keep != types.boolean:  # fmt: skip
        return None

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        target = context.make_array(double)(context, builder, value=args[0]).data
        source = context.make_array(double)(context, builder, value=args[2]).data
        for first, count in ((0, 4), (4, 2)):
            kind = ir.VectorType(ir.DoubleType(), count)
            offset = ir.IntType(64)(first)
            t = builder.bitcast(builder.gep(target, [builder.add(args[1], offset)]),
                                kind.as_pointer())  # fmt: skip
            f = builder.load(builder.bitcast(builder.gep(source, [builder.add(args[3], offset)]),
                                             kind.as_pointer()), align=8)  # fmt: skip
            old = builder.load(t, align=8)
            zero = ir.Constant(kind, [ir.DoubleType()(0.0)] * count)
            base = builder.select(args[4], old, zero)  # keep: a boolean, i1
            builder.store(builder.fsub(base, f), t, align=8)
        return context.get_dummy_value()

    return types.none(flat, into, w, at, keep), codegen


#: Typed view of the intrinsic for mypy (the same object for Numba).
subtract_record = cast("Callable[[np.ndarray, np.uint64, np.ndarray, np.uint64, bool], None]",
                       _subtract_record)  # fmt: skip


@nb.njit(inline="always", fastmath=FASTMATH)
def _log_special(x: float) -> float:
    """ln x where x is not positive and finite: NaN, -inf at 0, +inf at +inf."""
    if x == 0.0:
        return -np.inf
    return x if x > 0.0 else np.nan


@nb.njit(inline="always", fastmath=FASTMATH)
def log(x: float) -> float:
    """Natural logarithm, vectorisable, in the precision of ``x`` (:func:`log32`,
    :func:`log64`)."""
    if is_single(x):
        return like(x, log32(_single(x)))
    return like(x, log64(float(x)))


# The exponent and the cube-root guess are integer work on the float's bits. Written as 64-bit
# shifts, masks, adds and the bits of exact float sums, it vectorises on AVX2 too, which has no
# vector conversion between 64-bit integers and doubles and no 64-bit arithmetic shift (LLVM
# did those lane by lane: the cube root of a float32 array took 6.3 ns a value on an AVX2 EPYC,
# 4.3 now). Each helper gives exactly what the conversion it replaces gives.


@nb.njit(inline="always", fastmath=FASTMATH)
def _small_float(n: np.uint64) -> float:
    """float(n) for an integer 0 <= n < 2^52 (exact): 2^52 + n has n as its mantissa bits."""
    return bits_float(n | _TWO_52_BITS) - _TWO_52


@nb.njit(inline="always", fastmath=FASTMATH)
def _small_uint(d: float) -> np.uint64:
    """The integer d, for an integer-valued float 0 <= d < 2^52 (exact)."""
    return float_bits(d + _TWO_52) & _MANTISSA


@nb.njit(inline="always", fastmath=FASTMATH)
def _uint_float(n: np.uint64) -> float:
    """float(n) for an unsigned 64-bit n, rounded to nearest once, as a conversion rounds:
    (2^84 + 2^32 high) - (2^84 + 2^52) is exact, and adding 2^52 + low rounds."""
    high = bits_float((n >> _SHIFT_32) | _TWO_84_BITS) - _TWO_84_PLUS_52
    return high + bits_float((n & _LOW_32) | _TWO_52_BITS)


@nb.njit(inline="always", fastmath=FASTMATH)
def _float_uint(d: float) -> np.uint64:
    """The integer d, for an integer-valued float 2^52 <= d < 2^64 (exact, as a truncating
    conversion): its significand shifted left by its exponent less 52."""
    bits = float_bits(d)
    return ((bits & _MANTISSA) | _IMPLICIT_ONE) << ((bits >> _SHIFT_52) - _BIAS_52)


@nb.njit(inline="always", fastmath=FASTMATH)
def _log_sum(
    k: float,
    f: float,
    s: float,
    t1: float,
    t2: float,
    ln2_hi: float,
    ln2_lo: float,
) -> float:
    """fdlibm's ln x = k ln 2 + ln(1 + f) from f, s = f / (2 + f) and the polynomial's two
    parts t1, t2, summed in its order (k ln2_hi exact, the small terms first)."""
    hfsq = like(f, 0.5) * f * f
    return k * ln2_hi - ((hfsq - (s * (hfsq + t1 + t2) + k * ln2_lo)) - f)


@nb.njit(inline="always", fastmath=FASTMATH)
def log64(x: float) -> float:
    """Natural logarithm after fdlibm's e_log.c, within 2 ulp under fast-math; vectorisable.

    x = 2^k m with m in [sqrt(2)/2, sqrt(2)); ln x = k ln 2 + ln(1 + f), f = m - 1.
    """
    tiny = x < _SMALLEST_NORMAL
    bits = float_bits(x * _TWO_54 if tiny else x)
    m = bits_float((bits & _MANTISSA) | _ONE_BITS)  # [1, 2)
    high = m > _SQRT2
    m = 0.5 * m if high else m
    # k: the biased exponent less the bias (and 54 for a scaled subnormal), + 1 where m was halved
    dk = _small_float(bits >> _SHIFT_52) - (1077.0 if tiny else 1023.0) + (1.0 if high else 0.0)
    f = m - 1.0
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    t1 = w * (_LG2 + w * (_LG4 + w * _LG6))
    t2 = z * (_LG1 + w * (_LG3 + w * (_LG5 + w * _LG7)))
    result = _log_sum(dk, f, s, t1, t2, _LN2_HI, _LN2_LO)
    return result if x > 0.0 and x < np.inf else _log_special(x)


@nb.njit(inline="always", fastmath=FASTMATH)
def _inverse_cbrt_step(r: float, m: float) -> float:
    """One Newton step r (4 - m r^3) / 3 towards m^(-1/3): a relative error e becomes 2 e^2."""
    return r * (like(m, 4.0) - m * (r * r * r)) * like(m, 1.0 / 3.0)


@nb.njit(inline="always", fastmath=FASTMATH)
def _polished_cbrt(m: float, r: float) -> float:
    """m^(1/3) from r ~ m^(-1/3): y = m r^2 and one Newton step y - (y^3 - m) r^2 / 3."""
    r2 = r * r
    y = m * r2
    return y - (y * y * y - m) * r2 * like(m, 1.0 / 3.0)


@nb.njit(inline="always", fastmath=FASTMATH)
def _cbrt_reduced(m: float) -> float:
    """m^(1/3) for m in [1, 8), without a division.

    r = m^(-1/3) from a guess from the bits (within 3.5 %) and four Newton steps
    r (4 - m r^3) / 3 (the error e becomes 2 e^2), then y = m r^2 polished by one Newton step.
    """
    r = bits_float(_INVERSE_CBRT_MAGIC - _float_uint(_uint_float(float_bits(m)) * (1.0 / 3.0)))
    r = _inverse_cbrt_step(r, m)
    r = _inverse_cbrt_step(r, m)
    r = _inverse_cbrt_step(r, m)
    r = _inverse_cbrt_step(r, m)
    return _polished_cbrt(m, r)


@nb.njit(inline="always", fastmath=FASTMATH)
def cbrt(x: float) -> float:
    """Real cube root, vectorisable, in the precision of ``x`` (:func:`cbrt32`,
    :func:`cbrt64`)."""
    if is_single(x):
        return like(x, cbrt32(_single(x)))
    return like(x, cbrt64(float(x)))


@nb.njit(inline="always", fastmath=FASTMATH)
def cbrt64(x: float) -> float:
    """Real cube root, within about 1 ulp; vectorisable.

    |x| = 2^(3q + r) m with r in {0, 1, 2}, so cbrt|x| = 2^q (2^r m)^(1/3) with 2^r m in [1, 8).
    Zero, infinities and NaN pass through; negative x gives -cbrt(-x).
    """
    a = abs(x)
    tiny = a < _SMALLEST_NORMAL
    bits = float_bits(a * _TWO_54 if tiny else a)
    e = _small_float(bits >> _SHIFT_52) - 1023.0
    q = np.floor((e + 0.5) * (1.0 / 3.0))
    m = bits_float((bits & _MANTISSA) | (_small_uint(1023.0 + e - 3.0 * q) << _SHIFT_52))
    # 2^q, (2^54)^(1/3) = 2^18
    scale = bits_float(_small_uint(q + (1005.0 if tiny else 1023.0)) << _SHIFT_52)
    y = _cbrt_reduced(m) * scale
    y = y if a > 0.0 and a < np.inf else a  # 0, inf and NaN
    return y if x >= 0.0 else (-y if x < 0.0 else x)


@nb.njit(inline="always", fastmath=FASTMATH)
def log32(x: float) -> float:
    """Natural logarithm of a float32 after fdlibm's e_logf.c, in float32 arithmetic;
    vectorisable. As :func:`log64`: x = 2^k m, m in [sqrt(2)/2, sqrt(2)), ln(1 + f) in
    s = f / (2 + f)."""
    tiny = x < _SMALLEST_NORMAL_32
    scaled = x * _TWO_24_32 if tiny else x
    m = _significand32(scaled)  # [1, 2)
    high = m > _SQRT2_32
    m = like(x, 0.5) * m if high else m
    k = _exponent32(scaled) - like(x, 151.0 if tiny else 127.0) + like(x, 1.0 if high else 0.0)
    f = m - like(x, 1.0)
    s = f / (like(x, 2.0) + f)
    z = s * s
    w = z * z
    t1 = w * (_LG2_32 + w * _LG4_32)
    t2 = z * (_LG1_32 + w * _LG3_32)
    result = _log_sum(k, f, s, t1, t2, _LN2_HI_32, _LN2_LO_32)
    return result if x > like(x, 0.0) and x < _INF_32 else like(x, _log_special(float(x)))


@nb.njit(inline="always", fastmath=FASTMATH)
def cbrt32(x: float) -> float:
    """Real cube root of a float32, in float32 arithmetic; vectorisable. As :func:`cbrt64`:
    |x| = 2^(3q + r) m, three Newton steps on m^(-1/3) (3.5 % -> 2.5e-3 -> 1.2e-5 -> 3e-10), then
    y = m r^2 polished by one Newton step."""
    third = like(x, 1.0 / 3.0)
    a = abs(x)
    tiny = a < _SMALLEST_NORMAL_32
    scaled = a * _TWO_24_32 if tiny else a  # (2^24)^(1/3) = 2^8
    e = _exponent32(scaled) - like(x, 127.0)
    q = np.floor((e + like(x, 0.5)) * third)
    m = _significand32(scaled) * _power_of_two32(e - like(x, 3.0) * q)  # [1, 8), exact
    r = _inverse_cbrt_guess32(m)
    r = _inverse_cbrt_step(r, m)
    r = _inverse_cbrt_step(r, m)
    r = _inverse_cbrt_step(r, m)
    y = _polished_cbrt(m, r) * _power_of_two32(q - like(x, 8.0 if tiny else 0.0))
    y = y if a > like(x, 0.0) and a < _INF_32 else a  # 0, inf and NaN
    return y if x >= like(x, 0.0) else (-y if x < like(x, 0.0) else x)
