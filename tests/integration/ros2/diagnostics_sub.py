# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""diagnostics_sub.py - an independent ROS 2 /diagnostics subscriber.

The Python binding of Cyclone DDS (PyPI, its own libddsc: not the one
rtsup-trace loads) reads the DDS topic rt/diagnostics with the types
ROS 2 puts on the wire, written here from diagnostic_msgs' .msg files, and
prints every DiagnosticArray as one JSON line on stdout (flushed), with
the time it arrived, or with --echo as ros2 topic echo does. Runs until
killed or --count messages. Run it with the venv's python
(scripts/ros2-venv); the domain comes from ROS_DOMAIN_ID, the network from
CYCLONEDDS_URI, as for rtsup-trace.
"""
import argparse
import json
import os
import sys
import time
from dataclasses import dataclass

from cyclonedds.core import Qos, Policy
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import int32, uint32, byte, sequence
import cyclonedds.idl.annotations as annotate
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration


@dataclass
@annotate.final
class Time_(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


@dataclass
@annotate.final
class Header_(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time_
    frame_id: str


@dataclass
@annotate.final
class KeyValue_(IdlStruct, typename="diagnostic_msgs::msg::dds_::KeyValue_"):
    key: str
    value: str


@dataclass
@annotate.final
class DiagnosticStatus_(IdlStruct, typename="diagnostic_msgs::msg::dds_::DiagnosticStatus_"):
    level: byte
    name: str
    message: str
    hardware_id: str
    values: sequence[KeyValue_]


@dataclass
@annotate.final
class DiagnosticArray_(IdlStruct, typename="diagnostic_msgs::msg::dds_::DiagnosticArray_"):
    header: Header_
    status: sequence[DiagnosticStatus_]


def as_dict(msg):
    return {
        "header": {"stamp": {"sec": msg.header.stamp.sec,
                             "nanosec": msg.header.stamp.nanosec},
                   "frame_id": msg.header.frame_id},
        "status": [{"level": s.level, "name": s.name, "message": s.message,
                    "hardware_id": s.hardware_id,
                    "values": [{"key": v.key, "value": v.value} for v in s.values]}
                   for s in msg.status],
    }


def yaml_str(s):
    """A YAML scalar as ros2 topic echo writes it: quoted when it must be."""
    try:
        float(s)
        number = True
    except ValueError:
        number = False
    if (s == "" or number or s in ("-", "~") or s.lower() in ("true", "false", "null")
            or any(c in s for c in ":#'\"{}[],&*!|>%@`") or s.strip() != s):
        return "'" + s.replace("'", "''") + "'"
    return s


def as_echo(d):
    """The message in the layout of ros2 topic echo /diagnostics."""
    st = d["header"]["stamp"]
    out = ["header:", "  stamp:", "    sec: %d" % st["sec"], "    nanosec: %d" % st["nanosec"],
           "  frame_id: %s" % yaml_str(d["header"]["frame_id"]), "status:"]
    for s in d["status"]:
        out += ["- level: %d" % s["level"], "  name: %s" % yaml_str(s["name"]),
                "  message: %s" % yaml_str(s["message"]),
                "  hardware_id: %s" % yaml_str(s["hardware_id"]), "  values:"]
        for v in s["values"]:
            out += ["  - key: %s" % yaml_str(v["key"]), "    value: %s" % yaml_str(v["value"])]
    return "\n".join(out) + "\n---"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--count", type=int, default=0, help="stop after N messages")
    ap.add_argument("--echo", action="store_true",
                    help="as ros2 topic echo prints it, not JSON")
    args = ap.parse_args()
    domain = int(os.environ.get("ROS_DOMAIN_ID", "0") or 0)
    dp = DomainParticipant(domain)
    topic = Topic(dp, "rt/diagnostics", DiagnosticArray_)
    # ROS 2's default QoS: reliable, volatile, keep last 10
    qos = Qos(Policy.Reliability.Reliable(duration(milliseconds=100)),
              Policy.Durability.Volatile, Policy.History.KeepLast(10))
    reader = DataReader(dp, topic, qos=qos)
    if not args.echo:
        print(json.dumps({"ready": True}), flush=True)
    n = 0
    while not args.count or n < args.count:
        for msg in reader.take_iter(timeout=duration(seconds=1)):
            d = as_dict(msg)
            if args.echo:
                print(as_echo(d), flush=True)
            else:
                d["received"] = time.time()  # wall clock, as the stamp
                print(json.dumps(d), flush=True)
            n += 1
            if args.count and n >= args.count:
                break
    return 0


if __name__ == "__main__":
    sys.exit(main())
