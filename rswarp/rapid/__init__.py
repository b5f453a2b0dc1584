"""RAPID, ABB's robot language, read and run offline: a task's module files become the flat list of
``Motion`` records (every move and wait, in SI, with its file, line and call chain) that the
planner (``rswarp.motion``) times and checks. Nothing here imports Warp or the kinematics; this
package file imports nothing, so ``import rswarp.rapid`` stays light.

The pipeline:

1. **Parse** (``parse``, ``rapid.lark``): a file's bytes read, bounded and decoded, then lark's
   LALR parser, its inline transformer (``build``) making the tree as it parses; plain runs of
   targets and moves (``runs``) skip lark's per-token cost, and a syntax error is said where it
   was made (``syntax``).
2. **The tree** (``nodes``): frozen dataclasses, each with its line; a ``task`` is its modules
   with their names resolved as the controller resolves them, and ``check`` finds what the
   controller refuses when it loads a task, before any statement runs.
3. **Interpret** (``interpret``): the task's data declared and initialized, then the entry
   routine walked statement by statement, each call with a frame of its own data over its
   module's scope (``scope``); expressions (``expressions``), loops and branches (``flow``),
   built-in instructions (``instructions``) and functions (``functions``).
4. **Motion records** (``motion``, ``moves``, ``data``): each move instruction's target, speed,
   zone, tool and work object, converted to SI, handed to the planner; what the interpreter asks
   of the robot (CRobT, CalcJointT, ...) goes through ``motion.Robot``.

The word table, ``words.tsv`` (every instruction, function and data type of ABB's RAPID reference
manual, with its parameters), is read by ``words``, which says how rswarp handles each word
(modelled, no-op, live, unmodelled, state): ``check`` asks it whether a name exists and what its
arguments are (and which types the controller's configuration declares), ``instructions`` and
``functions`` what to do with a word they do not compute (run it as nothing, store a live read,
warn) and the controller's fixed state answers. ``python -m rswarp.rapid.words`` prints the table
for docs/program.md.

The modules:

- ``arguments``: a built-in's arguments read as its manual entry lays them out (by position, by
  name, switches), each evaluated when the routine asks.
- ``binding``: arguments bound to a routine's parameters as RAPID binds them (by value for IN;
  the caller's data, element or component for INOUT, VAR and PERS; optional and conditional ones).
- ``build``: lark's parse turned into ``nodes`` as it parses (operators, literals, strings, lines).
- ``byname``: data by name (GetDataVal, SetDataVal, SetAllDataVal, the symbol search) and
  GetSysData / SetSysData.
- ``calibration``: frames fitted to measured points (DefAccFrame, CalcRotAxisFrame).
- ``check``: the controller's load-time checks: unknown names, misspelt calls, arguments that do
  not fit, GOTO to a missing label.
- ``data``: RAPID's motion data (poses, tools, work objects, targets, speeds, zones) in SI,
  checked as the controller checks them before a move.
- ``eio``: a backup's I/O configuration (EIO.cfg): the signals the controller defines.
- ``errors``: ``fail``, the ``file:line: message`` error of a RAPID task.
- ``expressions``: expressions of a running task: names through frame, module and task, selectors,
  operators with RAPID's types, function calls.
- ``flow``: IF, TEST, FOR, WHILE and labels, loops that cannot end, and the exceptions by which
  control leaves a statement (GOTO, RETURN, EXIT, ExitCycle).
- ``functions``: the built-in functions (arithmetic, strings, bits, poses, I/O reads, clocks, the
  robot's state).
- ``handlers``: ERROR handlers with ERRNO, RETRY, TRYNEXT, RETURN and RAISE.
- ``instructions``: the built-in instructions (motion, waits, settings, data, signals, clocks).
- ``interpret``: the ``Interpreter``: one run of a task, statement by statement, with its limits
  (statements, call depth, the main loop's cycles).
- ``live``: values only a running cell has (sockets, files, the FlexPendant): unknown until
  ``--input`` gives them.
- ``loaded``: a task's data as the controller loads it, no routine run.
- ``motion``: what the interpreter hands the planner (``Motion``, ``Run``, ``Cycle``) and asks of
  it (``Robot``; ``NoRobot`` where there is none).
- ``moves``: the motion instructions (MoveJ, MoveL, MoveC, MoveAbsJ and their process forms) as
  ``Motion`` records, with the settings in force.
- ``nodes``: the tree a task is parsed into once and walked by the interpreter.
- ``parse``: reading a module file: bounded bytes, encodings, the ``%%%`` header, then lark.
- ``poses``: RAPID's pose arithmetic in its own units (Offs, RelTool, OrientZYX, PoseMult, ...).
- ``predefined``: the data every controller predefines (speeds, zones, tool0, wobj0, load0, ...).
- ``runs``: plain lines read without lark (declarations of literals, moves of names and numbers),
  each run one token of the text lark reads.
- ``scope``: where data lives while a task runs: ``Cell``, ``Part`` and ``Frame``, every write
  stamped so a loop's condition can be told unchanging.
- ``strings``: the string functions beyond the basic ones (StrToVal, StrMatch, StrMap, ...).
- ``syntax``: what a syntax error most likely is, said where the programmer made it.
- ``task``: a task as the controller loads it: its module files, parsed once, names resolved.
- ``values``: values at run time and their types (``Rec``, ``Arr``, ``Signal``; ``Types`` coerces
  an aggregate into a type).
- ``words``: the word table (``words.tsv``) and how rswarp handles each word.
"""
