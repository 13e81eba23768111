#!/usr/bin/env python3
"""checkpoint_edit.py -- read and edit the sections of an mpgm checkpoint
(DIR/checkpoint.mpgm; base/mpgm_blob.h), for tests that damage one on
purpose (tests/scripts/checkpoint_damage.sh, restart.sh).

A checkpoint is a sequence of sections, each a head of 36 bytes -- the tag
(24 bytes, NUL-padded), the length of the data (uint64), the CRC-32 of the
tag, the length and the data (uint32, zlib's) -- then the data, in the byte
order of the machine that wrote it (here: this one's).

  checkpoint_edit.py FILE list
      one line per section: index, byte offset, tag, length, CRC ok/BAD
  checkpoint_edit.py FILE flip TAG BYTE BIT
      flip bit BIT of byte BYTE of section TAG's data; the CRC is left as
      it was (the damage a disk or a copy does)
  checkpoint_edit.py FILE put TAG AT FORMAT VALUE [--crc]
      write VALUE packed as struct FORMAT (e.g. i, q, d, 64s) into section
      TAG's data at byte AT, or at item K of FORMAT when AT is #K; with
      --crc the section's CRC is recomputed, so that the checks of what the
      section holds, not the CRC, must find what is wrong
  checkpoint_edit.py FILE fix-crc
      recompute every section's CRC
  checkpoint_edit.py FILE format1
      rewrite the file as checkpoint format 1 wrote it (heads without a
      CRC, format 1 in the header): what an mpgm of before the CRCs left
"""
import struct
import sys
import zlib

TAG = 24
HEAD = TAG + 8 + 4


def sections(buf):
    """(offset, tag, length, recorded CRC, computed CRC) of each section."""
    out, at = [], 0
    while at + HEAD <= len(buf):
        tag = buf[at:at + TAG].split(b"\0", 1)[0].decode("ascii", "replace")
        (n,) = struct.unpack_from("=Q", buf, at + TAG)
        (rec,) = struct.unpack_from("=I", buf, at + TAG + 8)
        if at + HEAD + n > len(buf):
            raise SystemExit(f"section {tag!r} at byte {at} runs past the end of the file")
        crc = zlib.crc32(bytes(buf[at + HEAD:at + HEAD + n]), zlib.crc32(bytes(buf[at:at + TAG + 8])))
        out.append((at, tag, n, rec, crc))
        at += HEAD + n
    if at != len(buf):
        raise SystemExit(f"{len(buf) - at} bytes after the last section")
    return out


def find(buf, tag):
    for s in sections(buf):
        if s[1] == tag:
            return s
    raise SystemExit(f"no section {tag!r}")


def set_crc(buf, sec):
    at, _, n, _, _ = sec
    crc = zlib.crc32(bytes(buf[at + HEAD:at + HEAD + n]), zlib.crc32(bytes(buf[at:at + TAG + 8])))
    struct.pack_into("=I", buf, at + TAG + 8, crc)


def value(fmt, text):
    code = fmt.lstrip("=<>!@")[-1]
    if code == "s":
        return text.encode()
    if code in "efd":
        return float(text)
    return int(text, 0)


def main(argv):
    if len(argv) < 3:
        raise SystemExit(__doc__)
    path, cmd, args = argv[1], argv[2], argv[3:]
    buf = bytearray(open(path, "rb").read())
    if cmd == "list":
        for k, (at, tag, n, rec, crc) in enumerate(sections(buf)):
            print(f"{k:3d} {at:10d} {tag:24s} {n:10d} {'ok' if rec == crc else 'BAD'}")
        return
    if cmd == "flip":
        tag, byte, bit = args[0], int(args[1]), int(args[2])
        at, _, n, _, _ = find(buf, tag)
        if not 0 <= byte < n:
            raise SystemExit(f"section {tag!r} has {n} bytes")
        buf[at + HEAD + byte] ^= 1 << bit
    elif cmd == "put":
        tag, where, fmt, text = args[0], args[1], "=" + args[2], args[3]
        sec = find(buf, tag)
        at, _, n, _, _ = sec
        off = struct.calcsize(fmt) * int(where[1:]) if where.startswith("#") else int(where)
        if off < 0 or off + struct.calcsize(fmt) > n:
            raise SystemExit(f"section {tag!r} has {n} bytes, {fmt} at {off} does not fit")
        struct.pack_into(fmt, buf, at + HEAD + off, value(fmt, text))
        if "--crc" in args[4:]:
            set_crc(buf, sec)
    elif cmd == "format1":
        old = bytearray()
        for at, tag, n, _, _ in sections(buf):
            old += buf[at:at + TAG + 8] + buf[at + HEAD:at + HEAD + n]
        struct.pack_into("=I", old, TAG + 8 + 8, 1)  # the header's format field
        buf = old
    elif cmd == "fix-crc":
        for sec in sections(buf):
            set_crc(buf, sec)
    else:
        raise SystemExit(__doc__)
    open(path, "wb").write(buf)


if __name__ == "__main__":
    main(sys.argv)
