"""Navigation services: one navigation attempt from goal to arrival, with recoveries and events."""
