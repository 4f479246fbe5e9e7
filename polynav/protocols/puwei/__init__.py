"""The Puwei dialect: HTTP and WebSocket on one port (8080), login, tasks, UDP discovery
(``../shared/spec/puwei-api.md``). Adapters translate only (DESIGN §1)."""
