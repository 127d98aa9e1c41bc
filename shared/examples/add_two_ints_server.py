"""Serves example_interfaces/AddTwoInts on /add_two_ints."""

from __future__ import annotations

from zenros import Node, run
from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse


class AddTwoIntsServer(Node):
    """Adds two integers."""

    node_name = "add_two_ints_server"

    def setup(self) -> None:
        self.create_service(AddTwoInts, "add_two_ints", self.handle_add_two_ints)

    def handle_add_two_ints(self, req: AddTwoIntsRequest) -> AddTwoIntsResponse:
        return AddTwoIntsResponse(sum=req.a + req.b)


if __name__ == "__main__":
    run(AddTwoIntsServer)
