#!/usr/bin/env python3
"""Browse softnc's OPC UA server (docs/opcua.md) and read the machine's state.

    python3 clients/python/opcua_browse.py opc.tcp://127.0.0.1:4840/
    python3 clients/python/opcua_browse.py URL --user operator --password SECRET
    python3 clients/python/opcua_browse.py URL --wait-running 30   # until a program runs
    python3 clients/python/opcua_browse.py URL --wait-running 30 --min-line 4 --try-write
    python3 clients/python/opcua_browse.py URL --try-login          # accepted / refused
    python3 clients/python/opcua_browse.py URL --policies           # the logins offered

Browses Objects/Machines/<machine> by browse name (OPC 40501-1's namespace, softnc's for
its own variables) and prints one JSON object: Identification, the channel's ChannelState,
ChannelMode, FeedOverride, program, line and block (read together, in one request), the
spindle, the active program's production state, the standing alarms and the tool list.
With --try-write it also tries to set FeedOverride to 50 % and says how the server answered
(the server is read-only: refused). Needs `pip install asyncua`.
"""

import argparse
import asyncio
import json
import sys
import time

from asyncua import Client, ua

MACHINE_TOOL = "http://opcfoundation.org/UA/MachineTool/"
SOFTNC = "urn:softnc:UA"
CHANNEL_STATES = {0: "Active", 1: "Interrupted", 2: "Reset"}


async def child(node, ns, name):
    """The child of `node` with browse name ns:name, found by browsing its references."""
    for c in await node.get_children():
        bn = await c.read_browse_name()
        if bn.NamespaceIndex == ns and bn.Name == name:
            return c
    raise LookupError(f"no {ns}:{name} under {node}")


async def path(node, steps):
    for ns, name in steps:
        node = await child(node, ns, name)
    return node


async def value(node, steps):
    v = await (await path(node, steps)).read_value()
    return v.Text if isinstance(v, ua.LocalizedText) else v


async def read_machine(client):
    mt = await client.get_namespace_index(MACHINE_TOOL)
    own = await client.get_namespace_index(SOFTNC)
    machines = await child(client.nodes.objects, mt, "Machines")
    found = await machines.get_children()
    if not found:
        raise LookupError("Machines is empty")
    m = found[0]
    channel = [(mt, "Monitoring"), (mt, "Channel_1")]
    spindle = [(mt, "Monitoring"), (mt, "Spindle_1")]
    program = [(mt, "Production"), (mt, "ActiveProgram")]
    alarms = [(mt, "Notification"), (own, "Alarms")]
    ident = {
        n: await value(m, [(mt, "Identification"), (mt, n)])
        for n in ("Manufacturer", "Model", "SerialNumber", "SoftwareRevision")
    }
    state = await value(m, channel + [(mt, "ChannelState")])
    # Line and block in one Read: the server writes them together, so they match.
    line_node = await path(m, channel + [(own, "Line")])
    block_node = await path(m, channel + [(own, "Block")])
    line, block = await client.read_values([line_node, block_node])
    out = {
        "machine": (await m.read_browse_name()).Name,
        "identification": ident,
        "channel_state": CHANNEL_STATES.get(state, state),
        "channel_mode": await value(m, channel + [(mt, "ChannelMode")]),
        "feed_override": await value(m, channel + [(mt, "FeedOverride")]),
        "program": await value(m, channel + [(own, "ProgramName")]),
        "feed_rate": await value(m, channel + [(own, "FeedRate")]),
        "line": line,
        "block": block,
        "tool": await value(m, channel + [(own, "Tool")]),
        "edge": await value(m, channel + [(own, "Edge")]),
        "kernel_connected": await value(m, channel + [(own, "KernelConnected")]),
        "spindle_setpoint": await value(m, spindle + [(own, "SpeedSetpoint")]),
        "spindle_actual": await value(m, spindle + [(own, "SpeedActual")]),
        "spindle_rotating": await value(m, spindle + [(mt, "IsRotating")]),
        "active_program": await value(m, program + [(mt, "Name")]),
        "production_state": await value(m, program + [(mt, "State"), (mt, "CurrentState")]),
        "alarms": await value(m, alarms + [(own, "Numbers")]),
        "tools": [],
    }
    tools = await path(m, [(mt, "Equipment"), (mt, "Tools")])
    for t in await tools.get_children():
        if (await t.read_node_class()) != ua.NodeClass.Object:
            continue
        out["tools"].append({
            "name": (await t.read_browse_name()).Name,
            "t": await value(t, [(mt, "ControlIdentifier1")]),
            "d": await value(t, [(mt, "ControlIdentifier2")]),
            "radius": await value(t, [(own, "Radius")]),
            "length": await value(t, [(own, "Length")]),
        })
    return out


def client_for(args):
    client = Client(url=args.url, timeout=5)
    if args.user is not None:
        client.set_user(args.user)
    if args.password is not None:
        client.set_password(args.password)
    return client


async def try_write(client):
    """Tries to set FeedOverride to 50 %: `refused: <status>` or `written`, and the value
    read back."""
    mt = await client.get_namespace_index(MACHINE_TOOL)
    machines = await child(client.nodes.objects, mt, "Machines")
    m = (await machines.get_children())[0]
    node = await path(m, [(mt, "Monitoring"), (mt, "Channel_1"), (mt, "FeedOverride")])
    try:
        await node.write_value(ua.DataValue(ua.Variant(50.0, ua.VariantType.Double)))
        answer = "written"
    except ua.UaStatusCodeError as e:
        answer = f"refused: {type(e).__name__}"
    return {"answer": answer, "read_back": await node.read_value()}


async def identification(client):
    """The machine's serial number (its instance): readable with or without a kernel."""
    mt = await client.get_namespace_index(MACHINE_TOOL)
    machines = await child(client.nodes.objects, mt, "Machines")
    m = (await machines.get_children())[0]
    return await value(m, [(mt, "Identification"), (mt, "SerialNumber")])


async def try_login(args):
    try:
        async with client_for(args) as client:
            serial = await identification(client)
        print(f"accepted: {serial}")
    except Exception as e:  # the refusal's kind is the answer
        print(f"refused: {type(e).__name__}: {e}")


async def policies(args):
    """The user token policies of the server's endpoints, without a session."""
    client = Client(url=args.url, timeout=5)
    out = []
    for ep in await client.connect_and_get_server_endpoints():
        for p in ep.UserIdentityTokens:
            out.append({"type": p.TokenType.name, "security_policy": p.SecurityPolicyUri})
    print(json.dumps(out))


async def main(args):
    if args.policies:
        await policies(args)
        return 0
    if args.try_login:
        await try_login(args)
        return 0
    async with client_for(args) as client:
        deadline = time.monotonic() + args.wait_running
        while True:
            try:
                out = await read_machine(client)
            except ua.UaStatusCodeError as e:
                # Uncertain values: no kernel status yet (or any more).
                if args.wait_running == 0 or time.monotonic() > deadline:
                    raise
                out = {"error": str(e)}
            running = out.get("channel_state") == "Active" and out.get("line", 0) >= args.min_line
            if args.wait_running == 0 or running:
                if args.try_write:
                    out["feed_override_write"] = await try_write(client)
                print(json.dumps(out))
                return 0
            if time.monotonic() > deadline:
                print(json.dumps(out))
                print("the channel did not become Active (at --min-line) in time", file=sys.stderr)
                return 1
            await asyncio.sleep(0.1)


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("url")
    p.add_argument("--user")
    p.add_argument("--password")
    p.add_argument("--wait-running", type=float, default=0, metavar="SECONDS",
                   help="read until ChannelState is Active, at most this long")
    p.add_argument("--min-line", type=int, default=0, metavar="LINE",
                   help="with --wait-running: until the running line is at least LINE too")
    p.add_argument("--try-write", action="store_true",
                   help="also try to write FeedOverride and print the server's answer")
    p.add_argument("--try-login", action="store_true",
                   help="print whether the server takes this login")
    p.add_argument("--policies", action="store_true",
                   help="print the logins the server offers and how passwords are encrypted")
    sys.exit(asyncio.run(main(p.parse_args())))
