"""Local control: following a path with regulated pure pursuit, goal and progress checks."""
