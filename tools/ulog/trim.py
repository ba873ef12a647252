#!/usr/bin/env python3
"""Cut a PX4 ULog file down to a few topics (and optionally a time span), byte for byte.

    python3 tools/ulog/trim.py IN.ulg OUT.ulg --topics vehicle_local_position,vehicle_attitude
        [--from-s 0] [--to-s 30] [--keep-params]

The header, flag bits, formats and info messages are copied unchanged (multi-part info
messages, e.g. the boot log, are dropped); parameters only with
--keep-params (the ones the tests need, MAV_TYPE and SYS_AUTOSTART, are always kept). In the
data section only the subscriptions ('A') and data ('D') of the listed topics are kept (data
only within the span, measured from the first data message's timestamp), with dropouts and
sync markers; log text, other topics and parameter changes are dropped. Data appended after a
crash (the 'B' message's appended offsets) is not supported: such files are refused.

Used to make the small sample logs in tests/data/ from the BSD-licensed logs of
https://github.com/PX4/pyulog (test/*.ulg). Standard library only.
"""

import argparse
import struct
import sys

MAGIC = b"ULog\x01\x12\x35"
KEEP_PARAMS = (b"MAV_TYPE", b"SYS_AUTOSTART")


def messages(buf, pos):
    """(offset, type, payload) for every message from pos to the end (a cut tail is dropped)."""
    while pos + 3 <= len(buf):
        size, kind = struct.unpack_from("<HB", buf, pos)
        end = pos + 3 + size
        if end > len(buf):
            return
        yield pos, kind, buf[pos + 3:end]
        pos = end


def timestamp_offset(formats, name):
    """Byte offset of `timestamp` in topic `name` (always the first field in PX4 logs)."""
    fields = formats[name]
    off = 0
    sizes = {"int8_t": 1, "uint8_t": 1, "bool": 1, "char": 1, "int16_t": 2, "uint16_t": 2,
             "int32_t": 4, "uint32_t": 4, "float": 4, "int64_t": 8, "uint64_t": 8,
             "double": 8}
    for ty, fname in fields:
        if fname == "timestamp":
            return off
        base, _, count = ty.partition("[")
        n = int(count[:-1]) if count else 1
        off += sizes[base] * n
    raise ValueError(f"{name}: no timestamp")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--topics", required=True)
    ap.add_argument("--from-s", type=float, default=float("-inf"))
    ap.add_argument("--to-s", type=float, default=float("inf"))
    ap.add_argument("--keep-params", action="store_true")
    args = ap.parse_args()
    topics = set(args.topics.split(","))

    buf = open(args.input, "rb").read()
    if not buf.startswith(MAGIC):
        sys.exit(f"{args.input}: not a ULog file")
    out = bytearray(buf[:16])
    formats = {}
    keep_ids = {}
    t_first = None
    for pos, kind, payload in messages(buf, 16):
        raw = buf[pos:pos + 3 + len(payload)]
        c = chr(kind)
        if c == "B":
            if any(struct.unpack_from("<3Q", payload, 16)):
                sys.exit(f"{args.input}: appended data is not supported")
            out += raw
        elif c == "F":
            name, _, body = payload.decode("ascii").partition(":")
            formats[name] = [tuple(f.split(" ", 1)) for f in body.split(";") if f]
            out += raw
        elif c == "I":
            out += raw
        elif c in "PQ":
            klen = payload[0] if c == "P" else payload[1]
            key = payload[1:1 + klen] if c == "P" else payload[2:2 + klen]
            name = key.split(b" ", 1)[-1]
            if (args.keep_params or name in KEEP_PARAMS) and t_first is None:
                out += raw
        elif c == "A":
            multi_id, msg_id = struct.unpack_from("<BH", payload)
            name = payload[3:].decode("ascii")
            if name in topics:
                keep_ids[msg_id] = timestamp_offset(formats, name)
                out += raw
        elif c == "D":
            (msg_id,) = struct.unpack_from("<H", payload)
            if msg_id not in keep_ids:
                continue
            (ts,) = struct.unpack_from("<Q", payload, 2 + keep_ids[msg_id])
            if t_first is None:
                t_first = ts
            t = (ts - t_first) * 1e-6
            if args.from_s <= t <= args.to_s:
                out += raw
        elif c in "OS":
            out += raw
    open(args.output, "wb").write(out)
    print(f"{args.output}: {len(out)} bytes (from {len(buf)})")


if __name__ == "__main__":
    main()
