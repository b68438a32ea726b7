"""Python side of minibot3d's lock-step time (see participant.py)."""
from minibot3d_lockstep.participant import (  # noqa: F401
    ACK_TOPIC, LOCKSTEP_PARAM, PARTICIPANTS_TOPIC, REGISTER_SERVICE, UNREGISTER_SERVICE, Participant,
    action_server_ready, lockstep_enabled)
