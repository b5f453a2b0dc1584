"""A lanes block's configurations read and its poses stored, for ``fk_lanes``, eight lanes turned
into eight rows in registers (an 8x8 transpose) and back. A store writes each lane's row as one
piece, where storing number by number took an extract and a store for each; a read takes each
configuration's row whole and turns it into a column a joint.

A native snippet: Warp has no shuffle. Under clang (Warp's CPU compiler) the transpose is clang's
vector shuffles; any other compiler takes the plain loop. Either way each number is copied, not
computed, so what is stored is bit for bit what the lanes hold.
"""

import warp as wp

from .lane_algebra import LANES, VL

M34 = wp.types.matrix((3, 4), wp.float32)
M44 = wp.types.matrix((4, 4), wp.float32)
M88 = wp.types.matrix((8, 8), wp.float32)  # a block read: a row a column of q, a column a lane

# x0..x7 -> y[8]: y[ln] holds lane ln of each x (an 8x8 transpose by clang's vector shuffles)
_TRANSPOSE = r"""
rsw_v8 t0 = __builtin_shufflevector(x0, x1, 0, 8, 1, 9, 4, 12, 5, 13);
rsw_v8 t1 = __builtin_shufflevector(x0, x1, 2, 10, 3, 11, 6, 14, 7, 15);
rsw_v8 t2 = __builtin_shufflevector(x2, x3, 0, 8, 1, 9, 4, 12, 5, 13);
rsw_v8 t3 = __builtin_shufflevector(x2, x3, 2, 10, 3, 11, 6, 14, 7, 15);
rsw_v8 t4 = __builtin_shufflevector(x4, x5, 0, 8, 1, 9, 4, 12, 5, 13);
rsw_v8 t5 = __builtin_shufflevector(x4, x5, 2, 10, 3, 11, 6, 14, 7, 15);
rsw_v8 t6 = __builtin_shufflevector(x6, x7, 0, 8, 1, 9, 4, 12, 5, 13);
rsw_v8 t7 = __builtin_shufflevector(x6, x7, 2, 10, 3, 11, 6, 14, 7, 15);
rsw_v8 u0 = __builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13);
rsw_v8 u1 = __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15);
rsw_v8 u2 = __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13);
rsw_v8 u3 = __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15);
rsw_v8 u4 = __builtin_shufflevector(t4, t6, 0, 1, 8, 9, 4, 5, 12, 13);
rsw_v8 u5 = __builtin_shufflevector(t4, t6, 2, 3, 10, 11, 6, 7, 14, 15);
rsw_v8 u6 = __builtin_shufflevector(t5, t7, 0, 1, 8, 9, 4, 5, 12, 13);
rsw_v8 u7 = __builtin_shufflevector(t5, t7, 2, 3, 10, 11, 6, 7, 14, 15);
rsw_v8 y[8];
y[0] = __builtin_shufflevector(u0, u4, 0, 1, 2, 3, 8, 9, 10, 11);
y[1] = __builtin_shufflevector(u1, u5, 0, 1, 2, 3, 8, 9, 10, 11);
y[2] = __builtin_shufflevector(u2, u6, 0, 1, 2, 3, 8, 9, 10, 11);
y[3] = __builtin_shufflevector(u3, u7, 0, 1, 2, 3, 8, 9, 10, 11);
y[4] = __builtin_shufflevector(u0, u4, 4, 5, 6, 7, 12, 13, 14, 15);
y[5] = __builtin_shufflevector(u1, u5, 4, 5, 6, 7, 12, 13, 14, 15);
y[6] = __builtin_shufflevector(u2, u6, 4, 5, 6, 7, 12, 13, 14, 15);
y[7] = __builtin_shufflevector(u3, u7, 4, 5, 6, 7, 12, 13, 14, 15);
"""
_CLANG = ("#if defined(__clang__) && !defined(__CUDA_ARCH__)\n"
          "typedef float rsw_v8 __attribute__((ext_vector_type(8)));\n")

# rows a0..a7 (lane vectors) -> lane ln's row; then `nbytes` of it to lane ln's element of the
# block, `off` bytes into it, for the lanes below n
_BODY = _CLANG + r"""
rsw_v8 x0, x1, x2, x3, x4, x5, x6, x7;
__builtin_memcpy(&x0, &a0, 32); __builtin_memcpy(&x1, &a1, 32);
__builtin_memcpy(&x2, &a2, 32); __builtin_memcpy(&x3, &a3, 32);
__builtin_memcpy(&x4, &a4, 32); __builtin_memcpy(&x5, &a5, 32);
__builtin_memcpy(&x6, &a6, 32); __builtin_memcpy(&x7, &a7, 32);
""" + _TRANSPOSE + r"""
#else
float y[8][8];
for (int ln = 0; ln < 8; ++ln) {
    y[ln][0] = a0.c[ln]; y[ln][1] = a1.c[ln]; y[ln][2] = a2.c[ln]; y[ln][3] = a3.c[ln];
    y[ln][4] = a4.c[ln]; y[ln][5] = a5.c[ln]; y[ln][6] = a6.c[ln]; y[ln][7] = a7.c[ln];
}
#endif
char* base = (char*)out.data + (long long)i0 * out.strides[0] + BASE + off;
int m = n - i0 < 8 ? n - i0 : 8;
for (int ln = 0; ln < m; ++ln) __builtin_memcpy(base + (long long)ln * out.strides[0], &y[ln], nbytes);
"""
# rows i0..i0+7 of q (past n, the last again), each its first `dof` numbers (dof <= 8), as the
# rows of an 8x8 matrix a column of q each (rows past dof zero)
_LOAD = r"""
wp::mat_t<8, 8, wp::float32> qb;
int last = n - 1;
bool whole = q.strides[1] == (int)sizeof(float);
""" + _CLANG + r"""
if (whole) {
    rsw_v8 r[8];
    for (int ln = 0; ln < 8; ++ln) {
        int i = i0 + ln < last ? i0 + ln : last;
        r[ln] = (rsw_v8)(0.0f);
        __builtin_memcpy(&r[ln], (char*)q.data + (long long)i * q.strides[0], dof * sizeof(float));
    }
    rsw_v8 x0 = r[0], x1 = r[1], x2 = r[2], x3 = r[3], x4 = r[4], x5 = r[5], x6 = r[6], x7 = r[7];
""" + _TRANSPOSE + r"""
    for (int c = 0; c < 8; ++c) __builtin_memcpy(&qb.data[c][0], &y[c], 32);
    return qb;
}
#endif
for (int ln = 0; ln < 8; ++ln) {
    int i = i0 + ln < last ? i0 + ln : last;
    for (int c = 0; c < 8; ++c) qb.data[c][ln] = c < dof ? wp::index(q, i, c) : 0.0f;
}
return qb;
"""
_LINKS = _BODY.replace("BASE", "(long long)k * out.strides[1]")
_ONE = _BODY.replace("BASE", "0")

assert LANES == 8  # the transpose above is eight by eight


@wp.func_native(_LINKS)
def store_transforms(out: wp.array2d(dtype=wp.transformf), i0: int, n: int, k: int, off: int, nbytes: int,
                     a0: VL, a1: VL, a2: VL, a3: VL, a4: VL, a5: VL, a6: VL, a7: VL):
    """Lane ln of rows a0..a7 as ``nbytes`` of ``out[i0 + ln, k]`` from byte ``off``, lanes below n."""
    ...


@wp.func_native(_LINKS)
def store_mat44(out: wp.array2d(dtype=M44), i0: int, n: int, k: int, off: int, nbytes: int,
                a0: VL, a1: VL, a2: VL, a3: VL, a4: VL, a5: VL, a6: VL, a7: VL):
    """As ``store_transforms``, into 4x4 matrices."""
    ...


@wp.func_native(_LINKS)
def store_mat34(out: wp.array2d(dtype=M34), i0: int, n: int, k: int, off: int, nbytes: int,
                a0: VL, a1: VL, a2: VL, a3: VL, a4: VL, a5: VL, a6: VL, a7: VL):
    """As ``store_transforms``, into 3x4 matrices."""
    ...


@wp.func_native(_ONE)
def store_flange(out: wp.array(dtype=M44), i0: int, n: int, k: int, off: int, nbytes: int,
                 a0: VL, a1: VL, a2: VL, a3: VL, a4: VL, a5: VL, a6: VL, a7: VL):
    """As ``store_mat44``, into ``out[i0 + ln]`` (``k`` unread)."""
    ...


@wp.func_native(_LOAD)
def load_block(q: wp.array2d(dtype=wp.float32), i0: int, n: int, dof: int) -> M88:
    """Row c: column c of ``q`` at rows ``i0 .. i0 + 7`` (past n, the last again); zero past dof."""
    ...
