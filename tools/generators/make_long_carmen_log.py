#!/usr/bin/python3
"""Builds a long CARMEN log from a short one, to measure SLAM on long logs (memory, time, accuracy).

    tools/generators/make_long_carmen_log.py IN.clf REPEATS OUT.clf
        [--relations IN.relations OUT.relations]

The log is driven REPEATS times back and forth: repetitions 1, 3, 5... are the log as recorded,
repetitions 2, 4, ... the same messages in reverse order (the robot reverses along its own path,
its laser still facing forward). So the odometry is continuous without any offset — a reversed
repetition starts exactly where the previous one ended — and every scan is still consistent with
the building: no jump, no kidnapping, the area stays that of the original log while the trajectory
grows REPEATS times. Each repetition's timestamps (ipc and logger) are shifted to follow the
previous one one second later (reversed ones run backwards through the original times, so they
increase too); ODOM velocities are negated in reversed repetitions. PARAM and comment lines are
written once, at the top. Timestamps are shifted in exact decimal arithmetic with the log's own six
decimals, so a relations file can be shifted the same way (--relations): every relation is
repeated once per repetition with its two timestamps mapped like the log's (the relative pose of
two readings does not change when the robot drives the path again).

Only FLASER, ODOM, PARAM and comment lines are handled (the Intel log has no others); any other
message is refused, naming its line.
"""
import argparse
import decimal
import sys

decimal.getcontext().prec = 40
GAP = decimal.Decimal(1)  # s between repetitions
MESSAGES = ("FLASER", "ODOM")


def parse(path):
    header, messages = [], []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            fields = line.split()
            if not fields or fields[0].startswith("#"):
                header.append(line.rstrip("\n"))
            elif fields[0] == "PARAM":
                header.append(line.rstrip("\n"))
            elif fields[0] in MESSAGES:
                if len(fields) < 4:
                    sys.exit(f"{path}:{number}: truncated {fields[0]} line")
                try:
                    ipc, logger = decimal.Decimal(fields[-3]), decimal.Decimal(fields[-1])
                except decimal.InvalidOperation:
                    sys.exit(f"{path}:{number}: {fields[0]} line without numeric timestamps")
                messages.append((fields, ipc, logger))
            else:
                sys.exit(f"{path}:{number}: message type {fields[0]} is not handled (FLASER, ODOM, PARAM only)")
    if not messages:
        sys.exit(f"{path}: no FLASER or ODOM message")
    return header, messages


class TimeMap:
    """Where a repetition puts an original timestamp."""

    def __init__(self, first, last):
        self.first, self.last = first, last
        self.period = last - first + GAP

    def __call__(self, t, rep):
        if rep % 2 == 0:
            return t + rep * self.period
        return self.first + rep * self.period + (self.last - t)


def fmt(t):
    return f"{t:.6f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("log")
    ap.add_argument("repeats", type=int)
    ap.add_argument("out")
    ap.add_argument("--relations", nargs=2, metavar=("IN", "OUT"))
    a = ap.parse_args()
    if a.repeats < 1:
        sys.exit("REPEATS must be >= 1")
    header, messages = parse(a.log)
    ipc = TimeMap(min(m[1] for m in messages), max(m[1] for m in messages))
    logger = TimeMap(min(m[2] for m in messages), max(m[2] for m in messages))
    with open(a.out, "w") as out:
        for line in header:
            out.write(line + "\n")
        for rep in range(a.repeats):
            order = messages if rep % 2 == 0 else reversed(messages)
            for fields, t_ipc, t_logger in order:
                f = list(fields)
                f[-3] = fmt(ipc(t_ipc, rep))
                f[-1] = fmt(logger(t_logger, rep))
                if rep % 2 == 1 and f[0] == "ODOM":
                    f[4] = fmt(-decimal.Decimal(f[4]))  # tv
                    f[5] = fmt(-decimal.Decimal(f[5]))  # rv
                out.write(" ".join(f) + "\n")
    if a.relations:
        with open(a.relations[0]) as f_in, open(a.relations[1], "w") as f_out:
            rows = [line.split() for line in f_in if line.strip() and not line.startswith("#")]
            for rep in range(a.repeats):
                for r in rows:
                    t1, t2 = decimal.Decimal(r[0]), decimal.Decimal(r[1])
                    f_out.write(" ".join([fmt(ipc(t1, rep)), fmt(ipc(t2, rep))] + r[2:]) + "\n")
    seconds = (ipc.last - ipc.first) * a.repeats + GAP * (a.repeats - 1)
    print(f"{a.out}: {len(messages) * a.repeats} messages, {float(seconds):.1f} s of log")


if __name__ == "__main__":
    main()
