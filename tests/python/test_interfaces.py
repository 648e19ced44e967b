"""The interfaces table: every interface has a name, its ports, and a conversation that takes
bytes per direction; no port belongs to two interfaces."""
import urwire.interfaces as interfaces


def test_ports_are_unique_across_interfaces():
    seen = {}
    for interface in interfaces.INTERFACES.values():
        for port in interface.ports:
            assert port not in seen, f"port {port} in {seen.get(port)} and {interface.name}"
            seen[port] = interface.name


def test_primary_port_maps_to_primary_interface():
    assert interfaces.interface_of_port(30002).name == "ur"
    assert interfaces.interface_of_port(1) is None


def test_every_conversation_decodes_nothing_from_nothing():
    for interface in interfaces.INTERFACES.values():
        conversation = interface.conversation()
        assert conversation.feed(b"", True) == []
        assert conversation.feed(b"", False) == []
        assert conversation.close() == []
