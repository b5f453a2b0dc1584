"""The closed forms that solve a loop's passive joints, as one flat spec per passive joint (a row of
``Chain.closed``) that the FK kernels and the host read alike: ``[kind, ...]``, kind 0 for none.
The spec's input angle is ``Chain.closed_coef[k] @ q``."""

ANGLE, STROKE = 1, 2  # a balance cylinder's pivot angle, or its piston's stroke (rswarp.rsxml.slider)
FOUR_BAR = 3  # a passive joint of a planar four-bar (rswarp.rsxml.fourbar)
SPEC = 12  # the longest spec: the four-bar's [kind, V0..V3 (8), w (3)]
