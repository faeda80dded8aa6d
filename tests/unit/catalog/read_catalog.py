"""Reads a FITS catalog with astropy and prints what a user would see, one item per line:

    IMHEAD <hdu> <number of cards in the cell> <first card>
    TABLE <hdu> <extname> <rows>
    COLUMN <hdu> <name>|<unit>|<TDISP>|<TTYPE comment>|<first value>

Used by the catalog tests to check that astropy reads octarc's catalogs back.
"""
import sys

from astropy.io import fits
from astropy.table import Table


def main(path):
    with fits.open(path) as hdus:
        for index, hdu in enumerate(hdus):
            if not isinstance(hdu, fits.BinTableHDU):
                continue
            if hdu.name == "LDAC_IMHEAD":
                cards = hdu.data[0][0]
                print(f"IMHEAD {index} {len(cards)} {cards[0]}")
                continue
            table = Table.read(hdu)
            print(f"TABLE {index} {hdu.name} {len(table)}")
            for i, name in enumerate(hdu.columns.names, start=1):
                column = table[name]
                unit = "" if column.unit is None else column.unit.to_string(format="generic")
                raw_unit = hdu.header.get(f"TUNIT{i}", "")
                comment = hdu.header.comments[f"TTYPE{i}"]
                first = column[0] if len(column) else ""
                if hasattr(first, "__len__") and not isinstance(first, str):
                    first = first[0]
                print(f"COLUMN {index} {name}|{raw_unit}|{hdu.header.get(f'TDISP{i}', '')}|"
                      f"{comment}|{first}|{bool(unit) == bool(raw_unit)}")


if __name__ == "__main__":
    main(sys.argv[1])
