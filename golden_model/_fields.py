# SPDX-License-Identifier: MIT
"""The fixed classes of the generated data views (docs/conventions.md, generated views): register
fields and registers (golden_model/regs.py), the fields and layouts of the feature word and slot
(golden_model/featword.py) and the legal values of a parameter (golden_model/limits.py).

The generators in sw/orb_flow/gen/ write only data into those views; the classes that hold it
live here, as ordinary code.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property


@dataclass(frozen=True)
class Bits:
    """Bits lsb .. lsb + width - 1 of a word, named."""

    name: str
    lsb: int
    width: int

    @property
    def msb(self) -> int:
        return self.lsb + self.width - 1

    @property
    def mask(self) -> int:
        return ((1 << self.width) - 1) << self.lsb

    def get(self, word: int) -> int:
        """This field's value in a word."""
        return (word >> self.lsb) & ((1 << self.width) - 1)

    def put(self, value: int, word: int = 0) -> int:
        """word with this field set to value."""
        if not 0 <= value < 1 << self.width:
            raise ValueError(f"{self.name}: {value} does not fit {self.width} bits")
        return (word & ~self.mask) | (value << self.lsb)


@dataclass(frozen=True)
class RegField(Bits):
    """Bits lsb .. lsb + width - 1 of a register. reset is None when the value is a generic of
    orb_axil_regs (generic names it); port names the input a ro field shows; min and max are the
    smallest and largest legal written values (others answer SLVERR), max_generic a generic of
    orb_axil_regs whose value minus 1 is the largest; pulse fields read 0."""

    reset: int | None
    description: str
    generic: str | None = None
    port: str | None = None
    max: int | None = None
    pulse: bool = False
    min: int | None = None
    max_generic: str | None = None

    def legal_value(self, value: int, generics: Mapping[str, int] | None = None) -> bool:
        """Whether value may be written to this field (generics: NAME_g values for max_generic; a
        missing one leaves only the field's width as the maximum)."""
        top = (1 << self.width) - 1 if self.max is None else self.max
        if self.max_generic is not None and generics is not None and self.max_generic in generics:
            top = min(top, generics[self.max_generic] - 1)
        return (self.min or 0) <= value <= top


@dataclass(frozen=True)
class Register:
    """A 32-bit register at byte offset `offset`; access is ro, rw, w1c or wo."""

    name: str
    offset: int
    access: str
    fields: tuple[RegField, ...]
    description: str

    @cached_property
    def mask(self) -> int:
        """The defined bits (reserved bits read 0; setting one in a rw or wo write answers SLVERR)."""
        m = 0
        for f in self.fields:
            m |= f.mask
        return m

    @cached_property
    def bounded_fields(self) -> tuple[RegField, ...]:
        """The fields whose legal values are not simply every value of their width: a minimum, a
        maximum or a generic's (legal() checks these; any value of another field is legal)."""
        return tuple(f for f in self.fields if f.min or f.max is not None or f.max_generic is not None)

    def field(self, name: str) -> RegField:
        for f in self.fields:
            if f.name == name:
                return f
        raise KeyError(f"{self.name} has no field {name}")

    def reset_value(self, generics: Mapping[str, int] | None = None, ports: Mapping[str, int] | None = None) -> int:
        """The value read after reset; generic fields from `generics` (NAME_g keys), port fields
        from `ports` (default 0), pulse fields read 0."""
        word = 0
        for f in self.fields:
            if f.generic is not None:
                value = (generics or {})[f.generic]
            elif f.port is not None:
                value = (ports or {}).get(f.port, 0)
            else:
                value = 0 if f.pulse else f.reset or 0
            word |= (value << f.lsb) & f.mask
        return word

    def legal(self, word: int, generics: Mapping[str, int] | None = None) -> bool:
        """Whether a rw or wo write of word is accepted (no reserved bit set, every field within its
        minimum and maximum; generics: NAME_g values for the max_generic fields)."""
        if word & ~self.mask & 0xFFFFFFFF:
            return False
        bounded = self.bounded_fields
        return not bounded or all(f.legal_value(f.get(word), generics) for f in bounded)


@dataclass(frozen=True)
class WordField(Bits):
    """Bits lsb .. lsb + width - 1 of a word; `source` names the stream field a slot field carries."""

    meaning: str
    source: str | None = None


@dataclass(frozen=True)
class Layout:
    """One kind of word of `bits` bits: its fields and the value of the flag that marks it. Bits
    that are neither a field nor the flag are reserved (0 in every word the hardware writes)."""

    name: str
    bits: int
    flag: WordField
    flag_value: int
    fields: tuple[WordField, ...]

    @property
    def defined(self) -> int:
        """The mask of the fields and the flag."""
        m = self.flag.mask
        for f in self.fields:
            m |= f.mask
        return m

    @property
    def reserved(self) -> int:
        """The mask of the reserved bits."""
        return ((1 << self.bits) - 1) & ~self.defined

    def field(self, name: str) -> WordField:
        for f in self.fields:
            if f.name == name:
                return f
        raise KeyError(f"{self.name} has no field {name}")


@dataclass(frozen=True)
class Limit:
    """The legal values of one parameter: the integers min..max, only those in `values` when it is
    not empty, only powers of two when `power_of_two`; `text` writes them for messages. `generic` and
    `register` name the HDL generic and the read-back register field; `config` marks the parameters
    of golden_model.Config."""

    name: str
    min: int
    max: int
    text: str
    description: str
    values: tuple[int, ...] = ()
    power_of_two: bool = False
    generic: str | None = None
    register: str | None = None
    config: bool = False

    def legal(self, value: int) -> bool:
        """Whether the integer value is legal."""
        if self.values:
            return value in self.values
        if not self.min <= value <= self.max:
            return False
        return not self.power_of_two or value & (value - 1) == 0
