#!/usr/bin/env python3
"""Subscribes to a softnc instance's setpoints and status, as a HIL rig or a monitor would.

    python3 softnc_subscribe.py --instance NAME [--wait 30] [--seconds S] [--hold S] [--json]

Needs the iceoryx2 Python package of the version softnc is built with (``pip install
iceoryx2==0.10.0``; Cargo.toml names it). Start it before or during ``softnc run --instance
NAME PROGRAM``: it waits for the services, counts every setpoint and status sample, and ends
when the kernel has gone (``--hold`` seconds later; or after ``--seconds``, or at Ctrl-C)
with a summary: samples received, gaps in the sequence numbers (lost samples), the last
position per axis.

It is a client, not a part of the control: it only opens services that softnc's processes
created, and ``softnc run`` ends normally while it is still attached (docs/interfaces.md).
"""

import argparse
import json
import os
import signal
import sys
import time

import iceoryx2 as iox2

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import softnc_ipc as nc  # noqa: E402  (beside this file)


class Stream:
    """One subscribed service: the samples' sequence numbers and the newest sample."""

    def __init__(self, service, subscriber):
        self.service = service
        self.subscriber = subscriber
        self.count = 0
        self.first_seq = None
        self.first = None
        self.last_seq = None
        self.last = None
        self.gaps = 0
        self.lost = 0
        self.restarts = 0

    def drain(self):
        """Takes every sample that arrived; how many. Copies each: the sample goes back."""
        n = 0
        while True:
            sample = self.subscriber.receive()
            if sample is None:
                return n
            payload = sample.payload().contents
            msg = type(payload).from_buffer_copy(payload)
            sample.delete()
            self.take(msg)
            n += 1

    def take(self, msg):
        seq = msg.seq
        if self.last_seq is None:
            self.first_seq, self.first = seq, msg
        elif seq > self.last_seq + 1:
            # Publishers never block: a subscriber that falls behind loses its oldest samples.
            self.gaps += 1
            self.lost += seq - self.last_seq - 1
        elif seq <= self.last_seq:
            # 1, 2, … per kernel run: a new kernel started on the instance.
            self.restarts += 1
        self.last_seq, self.last = seq, msg
        self.count += 1

    def publishers(self):
        return self.service.dynamic_config.number_of_publishers


def instance_config(instance):
    """iceoryx2's configuration for a softnc instance: the default with the instance's prefix."""
    config = iox2.config.default()
    config.global_cfg.prefix = iox2.FileName.new(nc.prefix(instance))
    return config


def open_stream(node, instance, name, payload, deadline):
    """Opens `<instance>/<name>` once softnc has created it, requiring the ABI this module's
    layouts are (a softnc of another protocol is refused here, by name)."""
    service_name = iox2.ServiceName.new(nc.service_name(instance, name))
    verifier = iox2.AttributeVerifier.new().require(
        iox2.AttributeKey.new(nc.ABI_KEY), iox2.AttributeValue.new(nc.ABI)
    )
    while True:
        try:
            service = (
                node.service_builder(service_name)
                .publish_subscribe(payload)
                .open_with_attributes(verifier)
            )
            return Stream(service, service.subscriber_builder().create())
        except iox2.PublishSubscribeOpenError as e:
            retry = str(e) in ("DoesNotExist", "InsufficientPermissions", "ServiceInCorruptedState")
            if not retry or time.monotonic() > deadline:
                raise SystemExit(f"{nc.service_name(instance, name)}: cannot open: {e}") from None
            time.sleep(0.02)


def follow(setpoints, status, seconds, hold, quiet):
    """Drains both streams until the kernel has gone (its setpoint publisher with it), and
    stays attached `hold` seconds longer."""
    stop = []
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    end = time.monotonic() + seconds if seconds else None
    shown = time.monotonic()
    while not stop and (end is None or time.monotonic() < end):
        got = setpoints.drain() + status.drain()
        if setpoints.count and setpoints.publishers() == 0:
            # The kernel has ended: what it sent last may still be in the queue.
            setpoints.drain()
            status.drain()
            stay = time.monotonic() + hold
            while not stop and time.monotonic() < stay:
                time.sleep(0.05)
            break
        if not quiet and time.monotonic() - shown > 1.0 and setpoints.last is not None:
            shown = time.monotonic()
            print(progress(setpoints.last, status.last), flush=True)
        if not got:
            time.sleep(0.0005)


def axes_of(status, n):
    names = nc.axis_names(status.axes) if status is not None else ""
    return names if len(names) == n else "".join(f"{i}" for i in range(n))


def progress(sp, st):
    names = axes_of(st, sp.axes)
    pos = " ".join(f"{a}{sp.pos[i]:.3f}" for i, a in enumerate(names))
    return f"seq {sp.seq} line {sp.line} {nc.STATES.get(sp.state, '?')} {pos}"


def summary(setpoints, status):
    sp, st = setpoints.last, status.last
    n = sp.axes if sp is not None else 0
    names = axes_of(st, n)
    return {
        "setpoints": setpoints.count,
        "first_seq": setpoints.first_seq,
        "first_state": nc.STATES.get(setpoints.first.state) if setpoints.first else None,
        "last_seq": setpoints.last_seq,
        "gaps": setpoints.gaps,
        "lost": setpoints.lost,
        "restarts": setpoints.restarts,
        "status": status.count,
        "status_lost": status.lost,
        "state": nc.STATES.get(sp.state) if sp is not None else None,
        "alarm": st.alarm if st is not None else None,
        "axes": names,
        "pos": [sp.pos[i] for i in range(n)],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instance", default="softnc", help="softnc's --instance (default softnc)")
    ap.add_argument("--wait", type=float, default=30.0, help="seconds to wait for the services")
    ap.add_argument("--seconds", type=float, default=0.0, help="end after this long (0: never)")
    ap.add_argument(
        "--hold", type=float, default=0.0, help="stay attached this long after the kernel ended"
    )
    ap.add_argument("--json", action="store_true", help="the summary as one JSON line")
    ap.add_argument("--quiet", action="store_true", help="no progress lines")
    a = ap.parse_args()

    node = (
        iox2.NodeBuilder.new()
        .name(iox2.NodeName.new("python-subscriber"))
        .config(instance_config(a.instance))
        # Ctrl-C is ours: the summary is printed and the node dropped cleanly.
        .signal_handling_mode(iox2.SignalHandlingMode.Disabled)
        .create(iox2.ServiceType.Ipc)
    )
    print(f"waiting for {nc.service_name(a.instance, 'setpoints')}", file=sys.stderr, flush=True)
    deadline = time.monotonic() + a.wait
    setpoints = open_stream(node, a.instance, "setpoints", nc.SetpointMsg, deadline)
    status = open_stream(node, a.instance, "status", nc.KernelStatus, deadline)
    print("subscribed", file=sys.stderr, flush=True)
    follow(setpoints, status, a.seconds, a.hold, a.quiet or a.json)
    s = summary(setpoints, status)
    if a.json:
        print(json.dumps(s))
    else:
        pos = " ".join(f"{x}{p:.4f}" for x, p in zip(s["axes"], s["pos"]))
        print(
            f"{s['setpoints']} setpoints (seq {s['first_seq']}…{s['last_seq']}), "
            f"{s['lost']} lost in {s['gaps']} gaps; {s['status']} status samples; "
            f"last: {s['state']} {pos}"
        )
    # Ports before the node, as iceoryx2 wants: what this process holds is released here.
    del setpoints, status
    del node
    return 0


if __name__ == "__main__":
    sys.exit(main())
