"""``rswarp place``: where the robot should stand for a whole program. The task is run once for
every pose it moves to in the world (``poses``); the candidate bases (``candidates``) are solved
against every pose in one batch (``reach``), those that reach them all checked for collisions at
each pose (``clear``); the best few are run through the whole program and ranked by cycle time
(``run``), and the outputs written (``files``)."""
