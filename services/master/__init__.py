"""The master service: the parameter server and the registry of the computation graph."""
