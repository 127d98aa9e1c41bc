"""`MasterNode`: wires the parameter store, its replicas and the registry to Zenoh."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.home import data_dir
from zenros.node import Node

from .param_server import ParamServer
from .param_store import ParamStore
from .registry_server import RegistryServer
from .replica import Replicator

__all__ = ["DB_NAME", "MasterNode", "MasterParameters", "data_dir"]

DB_NAME = "params.db"


class MasterParameters(msgspec.Struct, kw_only=True):
    """The master's own parameters (from the command line or a params file, never a master)."""

    data_dir: Annotated[str, Meta(description="where params.db lives (default $ZENROS_HOME "
                                              "or ~/.zenros)")] = ""
    sync_period: Annotated[float, Meta(ge=0, description="seconds between anti-entropy pulls "
                                                         "from other replicas (0: only on "
                                                         "events)")] = 5.0
    sync_timeout: Annotated[float, Meta(ge=0, description="how long a pull waits for replicas "
                                                          "to answer (s)")] = 2.0
    registry_grace: Annotated[float, Meta(ge=0, description="seconds a vanished liveliness "
                                                            "token is kept")] = 2.0


class MasterNode(Node):
    """The parameter server and the registry of the computation graph.

    Parameters: `MasterParameters`.
    """

    node_name = "master"
    uses_parameter_server = False  # the master's own parameters never come from a master

    def setup(self) -> None:
        p = self.declare_parameters(MasterParameters)
        self.store = self.own(ParamStore(data_dir(p.data_dir) / DB_NAME))
        self.logger.info("parameters in %s (%d names, replica %s)", self.store.path,
                         len(self.store.names()), self.store.source)
        self.replicator = self.own(Replicator(self, self.store, period=p.sync_period,
                                              timeout=p.sync_timeout))
        self.params = self.own(ParamServer(self, self.store))
        # flaps shorter than the grace are ignored
        self.registry = self.own(RegistryServer(self, p.registry_grace))
