"""Bags: record, play, inspect and recover topic traffic in MCAP files (Foxglove-readable).

`Recorder` writes raw samples (JSON or MessagePack, as they travel) with a JSON Schema per
type; `Player` republishes them on their original schedule; `bag_info` summarizes a bag;
`recover_bag` rebuilds the files of a recorder that was killed. Bags recorded with ROS
(rosbag2, ROS 1) are read too, converted to zenros's messages (`zenros.bag.foreign`, the
``rosbags`` extra).
"""

from .info import BagInfo, bag_info, format_info
from .player import Player, PlayOptions
from .reader import BagError, BagMessage, bag_files, bags_home, iter_messages, resolve_bag
from .recorder import Recorder, RecordOptions
from .recover import Recovered, recover_bag, recover_file
from .sink import BagSink, SplitPolicy

__all__ = [
    "BagError",
    "BagInfo",
    "BagMessage",
    "BagSink",
    "PlayOptions",
    "Player",
    "RecordOptions",
    "Recorder",
    "Recovered",
    "SplitPolicy",
    "bag_files",
    "bag_info",
    "bags_home",
    "format_info",
    "iter_messages",
    "recover_bag",
    "recover_file",
    "resolve_bag",
]
