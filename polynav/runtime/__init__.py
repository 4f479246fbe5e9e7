"""The runtime: one robot's clock, backend and services, advanced together."""
