"""urwire's live tools, on sockets: `urwire serve` (serve.py), a simulated robot cell on every
interface (the controller of simulated.py, its motion and models, the state they share in
robot_cell.py, a session module per interface), and `urwire listen` (listen.py), which records
and decodes a robot's streams as they come. They decode with the core package (urwire) and
import nothing from urwire.data.
"""
