"""The diagnostics aggregator service: ``/diagnostics`` in, the analyzed tree out on
``/diagnostics_agg`` and the robot's overall state on ``/diagnostics_toplevel_state``."""
