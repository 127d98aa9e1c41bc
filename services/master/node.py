"""`MasterNode`: wires the parameter store, its replicas and the registry to Zenoh."""

from __future__ import annotations

from zenros.home import data_dir
from zenros.node import Node

from .param_server import ParamServer
from .param_store import ParamStore
from .registry_server import RegistryServer
from .replica import Replicator

__all__ = ["DB_NAME", "MasterNode", "data_dir"]

DB_NAME = "params.db"


class MasterNode(Node):
    """The parameter server and the registry of the computation graph.

    Parameters:
        data_dir: where ``params.db`` lives (default ``$ZENROS_HOME`` or ``~/.zenros``).
        sync_period: seconds between anti-entropy pulls from other replicas (0: only on
            events).
        sync_timeout: how long a pull waits for replicas to answer.
        registry_grace: seconds a vanished liveliness token is kept (flaps are ignored).
    """

    node_name = "master"
    uses_parameter_server = False  # the master's own parameters never come from a master

    def setup(self) -> None:
        directory = data_dir(self.declare_parameter("data_dir", ""))
        period = self.declare_parameter("sync_period", 5.0)
        timeout = self.declare_parameter("sync_timeout", 2.0)
        grace = self.declare_parameter("registry_grace", 2.0)
        self.store = ParamStore(directory / DB_NAME)
        self.logger.info("parameters in %s (%d names, replica %s)", self.store.path,
                         len(self.store.names()), self.store.source)
        self.replicator = Replicator(self, self.store, period=period, timeout=timeout)
        self.params = ParamServer(self, self.store)
        self.registry = RegistryServer(self, grace)

    def close(self) -> None:
        for part in ("registry", "params", "replicator"):
            obj = getattr(self, part, None)
            if obj is not None:
                obj.close()
        super().close()
        store = getattr(self, "store", None)
        if store is not None:
            store.close()
