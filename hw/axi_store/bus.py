"""AXI4 (full) manager port: the five channels as wiring signatures, and the constants the
state store's port drives.

Signal names are the AXI ones (``araddr``, ``awlen``, ``wstrb``, ``rlast`` …); a top level
that flattens them with a prefix gets ``m_axi_state_araddr`` and so on. The signature is
seen from the manager: ``Out`` members are driven by the manager, ``In`` members by the
subordinate (memory).
"""

from __future__ import annotations

from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import AxiStoreConfig

__all__ = ["BURST_INCR", "RESP_OKAY", "RESP_EXOKAY", "RESP_SLVERR", "RESP_DECERR",
           "CACHE_MODIFIABLE", "AXI_PREFIX", "axi4_signature", "address_channel", "size_code",
           "axi_port_members", "store_port_members", "connect_axi_ports"]

#: ``AxBURST`` of an incrementing burst.
BURST_INCR = 0b01
#: ``RRESP`` / ``BRESP`` codes; bit 1 set means an error (SLVERR, DECERR).
RESP_OKAY, RESP_EXOKAY, RESP_SLVERR, RESP_DECERR = 0b00, 0b01, 0b10, 0b11
#: ``AxCACHE`` the port drives: normal non-cacheable bufferable (0b0011), what a DMA
#: engine streaming to DRAM uses.
CACHE_MODIFIABLE = 0b0011
#: Prefix of the flattened AXI4 manager port: ``m_axi_state_araddr`` and so on.
AXI_PREFIX = "m_axi_state"


def size_code(beat_bytes: int) -> int:
    """``AxSIZE`` of full-width beats: ``log2(beat_bytes)``."""
    return beat_bytes.bit_length() - 1


def address_channel(prefix: str, address_bits: int, id_bits: int) -> wiring.Signature:
    """The AR (``prefix="ar"``) or AW (``"aw"``) channel, manager's view."""
    return wiring.Signature({
        f"{prefix}id": Out(id_bits),
        f"{prefix}addr": Out(address_bits),
        f"{prefix}len": Out(8),
        f"{prefix}size": Out(3),
        f"{prefix}burst": Out(2),
        f"{prefix}lock": Out(1),
        f"{prefix}cache": Out(4),
        f"{prefix}prot": Out(3),
        f"{prefix}qos": Out(4),
        f"{prefix}valid": Out(1),
        f"{prefix}ready": In(1),
    })


def axi4_signature(store: AxiStoreConfig) -> wiring.Signature:
    """AXI4 as the manager sees it: channels ``aw``, ``w``, ``b``, ``ar``, ``r``, with
    ``store``'s address, data and ID widths."""
    a, d, i = store.address_bits, store.data_bits, store.id_bits
    return wiring.Signature({
        "aw": Out(address_channel("aw", a, i)),
        "w": Out(wiring.Signature({"wdata": Out(d), "wstrb": Out(d // 8), "wlast": Out(1),
                                   "wvalid": Out(1), "wready": In(1)})),
        "b": Out(wiring.Signature({"bid": In(i), "bresp": In(2), "bvalid": In(1),
                                   "bready": Out(1)})),
        "ar": Out(address_channel("ar", a, i)),
        "r": Out(wiring.Signature({"rid": In(i), "rdata": In(d), "rresp": In(2),
                                   "rlast": In(1), "rvalid": In(1), "rready": Out(1)})),
    })


def axi_port_members(store: AxiStoreConfig) -> dict:
    """``{m_axi_state_<AXI name>: member}`` of the state store's AXI4 manager port."""
    return {f"{AXI_PREFIX}_{path[-1]}": member
            for path, member in axi4_signature(store).members.flatten() if member.is_port}


def store_port_members(store: AxiStoreConfig) -> dict:
    """The members a component with the store outside has beyond its own: the flattened
    manager port, the base address (reset: the configured one) and the error pulses."""
    return {**axi_port_members(store),
            "state_base": In(store.address_bits, init=store.base_address),
            "read_error": Out(1),
            "write_error": Out(1)}


def connect_axi_ports(store: AxiStoreConfig, outer, inner) -> list:
    """The statements that pass ``inner``'s flattened manager port through ``outer``'s
    (outputs outward, inputs inward)."""
    return [getattr(outer, name).eq(getattr(inner, name)) if member.flow == Out
            else getattr(inner, name).eq(getattr(outer, name))
            for name, member in axi_port_members(store).items()]
