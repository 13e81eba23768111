#!/usr/bin/env python3
"""code_shape.py -- the house rules on the shape of the C code.

    usage: code_shape.py [--max-function N] [--max-file N] DIR_OR_FILE...

No function over 120 lines and no .c/.h file over 800 lines (the defaults).
Folders are walked recursively for *.c and *.h files, skipping any folder
named build* or .git; a file given by name is checked whatever its name.
Reports

    FILE: N lines (limit 800)
    FILE:LINE: function NAME: N lines (limit 120)

for each file / function over its limit, then one line
"N files, M functions checked; K over the limits", and exits 1 when K > 0
(2 on a usage error or a missing path).

A function's length runs from the line where its name appears through the
line of its closing brace, inclusive.  A function definition is a brace at
depth 0 that follows a ')' (attributes such as __attribute__((...)) may
stand between), outside struct/union/enum bodies and initialisers ('= {').
Comments, string and character literals and preprocessor lines (including
backslash-continued ones, so a do { } while (0) macro is not counted) are
blanked before scanning; newlines are kept so line numbers stay right.
extern "C" { ... } blocks add no depth.  Modern C only: K&R parameter
declarations are not recognised, and #if branches are not evaluated (a file
whose braces then do not balance gets a warning on stderr).
"""
import argparse
import os
import re
import sys

ATTRIBUTE_WORDS = {"__attribute__", "__attribute", "__declspec"}
C_KEYWORDS = set("""
    auto break case char const continue default do double else enum extern
    float for goto if inline int long register restrict return short signed
    sizeof static struct switch typedef union unsigned void volatile while
    _Alignas _Alignof _Atomic _Bool _Complex _Generic _Imaginary _Noreturn
    _Static_assert _Thread_local typeof __typeof__ __inline __inline__
    __restrict __restrict__ __extension__ __asm__ asm
    """.split())
TOKEN_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|\d[\w.]*|\S")


def clean(text):
    """Return text with comments, literals and preprocessor lines blanked.

    Every character except '\\n' that belongs to a comment, the inside of a
    string/char literal or a preprocessor directive becomes a space, so the
    result has the same lines (and columns) as the input.
    """
    out = []
    i, n = 0, len(text)
    line_start = True    # only whitespace seen since the last newline
    directive = False    # inside a preprocessor directive
    while i < n:
        c = text[i]
        nxt = text[i + 1] if i + 1 < n else ""
        if c == "\n":
            out.append(c)
            i += 1
            line_start = True
            directive = False
            continue
        if c == "\\" and nxt == "\n":       # line splice: keep the newline
            out.append(" \n")
            i += 2
            continue
        if c == "\\" and text.startswith("\r\n", i + 1):
            out.append("  \n")
            i += 3
            continue
        if c == "/" and nxt == "*":         # block comment
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c == "/" and nxt == "/":         # line comment (may be spliced)
            j = i
            while j < n and text[j] != "\n":
                if text[j] == "\\" and text.startswith("\n", j + 1):
                    j += 2
                elif text[j] == "\\" and text.startswith("\r\n", j + 1):
                    j += 3
                else:
                    j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        if c in "\"'":                      # literal; ends at its quote or
            j = i + 1                       # at an unspliced newline
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j, n)
            body = re.sub(r"[^\n]", " ", text[i + 1:j])
            closed = j < n and text[j] == c
            keep = " " if directive else c
            out.append(keep + body + (keep if closed else ""))
            i = j + 1 if closed else j
            line_start = False
            continue
        if c == "#" and line_start:
            directive = True
        if not c.isspace():
            line_start = False
        out.append(" " if directive and not c.isspace() else c)
        i += 1
    return "".join(out)


def tokens(cleaned):
    """(text, line) for every token of the cleaned source."""
    result = []
    for lineno, line in enumerate(cleaned.split("\n"), start=1):
        for m in TOKEN_RE.finditer(line):
            result.append((m.group(0), lineno))
    return result


def skip_back_group(toks, k, open_, close):
    """toks[k] is `close`; return the index of its matching `open_`."""
    depth = 0
    while k >= 0:
        t = toks[k][0]
        if t == close:
            depth += 1
        elif t == open_:
            depth -= 1
            if depth == 0:
                return k
        k -= 1
    return -1


def header_end(toks, k, start):
    """Skip attributes backwards from toks[k]; return the index of the
    token the brace really follows (or -1)."""
    while k >= start:
        t = toks[k][0]
        if t == ")":
            o = skip_back_group(toks, k, "(", ")")
            if o > start and toks[o - 1][0] in ATTRIBUTE_WORDS:
                k = o - 2
                continue
            return k
        if t == "]" and k - 1 >= start and toks[k - 1][0] == "]":
            o = skip_back_group(toks, k, "[", "]")    # C23 [[attribute]]
            if o > start and toks[o][0] == "[" and toks[o + 1][0] == "[":
                k = o - 1
                continue
            return k
        return k
    return -1


def function_name(toks, close, start):
    """Name of the function whose parameter list ends at toks[close]."""
    o = skip_back_group(toks, close, "(", ")")
    if o - 1 >= start and re.match(r"[A-Za-z_]", toks[o - 1][0]) \
            and toks[o - 1][0] not in ATTRIBUTE_WORDS:
        return o - 1
    # A function returning a function pointer, void (*f(int))(double): the
    # name is the innermost identifier (not a keyword) followed by '('.
    best, best_depth, depth, k = -1, -1, 0, start
    while k < close:
        t = toks[k][0]
        if t in ATTRIBUTE_WORDS and toks[k + 1][0] == "(":
            depth_here = 0              # skip __attribute__((...)) whole
            k += 1
            while k < close:
                depth_here += {"(": 1, ")": -1}.get(toks[k][0], 0)
                if depth_here == 0:
                    break
                k += 1
        elif re.match(r"[A-Za-z_]", t) and toks[k + 1][0] == "(" \
                and t not in C_KEYWORDS and depth > best_depth:
            best, best_depth = k, depth
        if t == "(":
            depth += 1
        elif t == ")":
            depth -= 1
        k += 1
    return best


def is_initialiser(toks, start, end):
    """True if toks[start:end] has an '=' outside parentheses/brackets."""
    depth = 0
    for k in range(start, end):
        t = toks[k][0]
        if t in "([":
            depth += 1
        elif t in ")]":
            depth -= 1
        elif t == "=" and depth == 0:
            return True
    return False


def functions(cleaned):
    """([(name, first_line, last_line)], balanced) for the function
    definitions; balanced is False when the braces do not pair up (e.g.
    both branches of an #if open a brace), so the result is doubtful."""
    toks = tokens(cleaned)
    found = []
    depth = 0
    linkage = 0             # open extern "C" { blocks (they add no depth)
    stmt_start = 0          # first token of the current top-level statement
    current = None          # (name, line) of the function being scanned
    balanced = True
    for k, (t, line) in enumerate(toks):
        if t == "{" and depth == 0 and k >= 3 and toks[k - 1][0] == '"' \
                and toks[k - 2][0] == '"' and toks[k - 3][0] == "extern":
            linkage += 1        # extern "C" { (from a cleaned "C" literal)
            stmt_start = k + 1
            continue
        if t == "}" and depth == 0:
            if linkage:
                linkage -= 1
            else:
                balanced = False
            stmt_start = k + 1
            continue
        if t == "{":
            if depth == 0:
                current = None
                end = header_end(toks, k - 1, stmt_start)
                if end >= stmt_start and toks[end][0] == ")" \
                        and not is_initialiser(toks, stmt_start, end):
                    nk = function_name(toks, end, stmt_start)
                    if nk >= 0:
                        current = (toks[nk][0], toks[nk][1])
                    else:
                        current = ("?", line)
            depth += 1
        elif t == "}":
            depth -= 1
            if depth == 0:
                if current is not None:
                    found.append((current[0], current[1], line))
                    current = None
                stmt_start = k + 1
        elif t == ";" and depth == 0:
            stmt_start = k + 1
    return found, balanced and depth == 0 and linkage == 0


def line_count(text):
    return text.count("\n") + (1 if text and not text.endswith("\n") else 0)


def source_files(paths):
    files = []
    for p in paths:
        if os.path.isfile(p):
            files.append(p)
            continue
        if not os.path.isdir(p):
            print(f"code_shape.py: {p}: no such file or directory",
                  file=sys.stderr)
            sys.exit(2)
        for root, dirs, names in os.walk(p):
            dirs[:] = sorted(d for d in dirs
                             if not d.startswith("build") and d != ".git")
            for name in sorted(names):
                if name.endswith((".c", ".h")):
                    files.append(os.path.join(root, name))
    seen = set()
    return [f for f in files if not (f in seen or seen.add(f))]


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Report C functions and files over the size limits.")
    ap.add_argument("--max-function", type=int, default=120, metavar="N",
                    help="longest function allowed, in lines (120)")
    ap.add_argument("--max-file", type=int, default=800, metavar="N",
                    help="longest .c/.h file allowed, in lines (800)")
    ap.add_argument("paths", nargs="+", metavar="DIR_OR_FILE")
    args = ap.parse_args(argv)

    files = source_files(args.paths)
    n_functions = over = 0
    for path in files:
        with open(path, encoding="utf-8", errors="replace", newline="") as f:
            text = f.read()
        n_lines = line_count(text)
        if n_lines > args.max_file:
            print(f"{path}: {n_lines} lines (limit {args.max_file})")
            over += 1
        found, balanced = functions(clean(text))
        if not balanced:
            print(f"code_shape.py: warning: {path}: braces do not balance "
                  "(#if branches?); function lengths may be wrong",
                  file=sys.stderr)
        for name, first, last in found:
            n_functions += 1
            length = last - first + 1
            if length > args.max_function:
                print(f"{path}:{first}: function {name}: {length} lines "
                      f"(limit {args.max_function})")
                over += 1
    print(f"{len(files)} files, {n_functions} functions checked; "
          f"{over} over the limits")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
