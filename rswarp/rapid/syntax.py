"""What a syntax error most likely is, said where the programmer made it: a block opened and never
closed (``ENDFI`` for ``ENDIF``: the IF's line, not the ENDMODULE's the parser met), a statement
without its ``;`` (the line it ends on, not the next), a file that is XML, not RAPID."""

from __future__ import annotations

import re

from .build import STRING

_WORDS = re.compile(STRING + r"|![^\n]*|\b(IF|THEN|ELSEIF|ENDIF|FOR|ENDFOR|WHILE|ENDWHILE|TEST|ENDTEST|PROC|ENDPROC|"
                    r"FUNC|ENDFUNC|TRAP|ENDTRAP|RECORD|ENDRECORD|MODULE|ENDMODULE)\b|;", re.I)
_CLOSES = {"endif": "if", "endfor": "for", "endwhile": "while", "endtest": "test", "endproc": "proc",
           "endfunc": "func", "endtrap": "trap", "endrecord": "record", "endmodule": "module"}


def unclosed(text: str) -> tuple[int, str] | None:
    """(line, message) of the first block closed by the wrong END, or never closed."""
    stack: list[tuple[str, int]] = []
    pending_if = None  # an IF not yet known to open a block (THEN) or be one line (;)
    line = 1
    at = 0
    for m in _WORDS.finditer(text):
        line += text.count("\n", at, m.start())
        at = m.start()
        word = (m.group(1) or "").lower()
        if m.group(0) == ";":
            pending_if = None
        elif word == "if":
            pending_if = line
        elif word == "then" and pending_if is not None:
            stack.append(("if", pending_if))
            pending_if = None
        elif word in ("for", "while", "test", "proc", "func", "trap", "record", "module"):
            stack.append((word, line))
        elif word in _CLOSES:
            want = _CLOSES[word]
            if not stack or stack[-1][0] != want:
                if stack:
                    kind, opened = stack[-1]
                    return opened, (f"RAPID syntax: {kind.upper()} has no END{kind.upper()} ({word.upper()} at line "
                                    f"{line})")
                return line, f"RAPID syntax: {word.upper()} closes nothing"
            stack.pop()
    if stack:
        kind, opened = stack[-1]
        return opened, f"RAPID syntax: {kind.upper()} has no END{kind.upper()}"
    return None


def explained(text: str, line: int, token, expected) -> tuple[int, str]:
    """(line, message) of an unexpected ``token`` met at ``line``, said where it was likely made."""
    if text.lstrip().startswith("<"):
        return 1, "an XML file, not a RAPID module (a .pgf program file names its modules)"
    if not re.sub(r"!.*", "", text).strip():
        return 1, "no MODULE in the file (empty, or only comments): a RAPID module file holds MODULE ... ENDMODULE"
    block = unclosed(text)
    if block is not None and (token is None or block[0] <= line):
        return block
    if token is not None and "SEMICOLON" in expected:
        before = text[:token.start_pos].rstrip()
        end = before.count("\n") + 1
        if end < line:
            return end, f"RAPID syntax: ';' missing at the end of the line (line {line} goes on with {str(token)!r})"
    if token is None:
        return line, "RAPID syntax: the file ends before its statement or block does"
    return line, f"RAPID syntax: unexpected {str(token)[:40]!r}"
