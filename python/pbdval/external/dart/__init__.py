"""DART (dartpy) as a pbdval external engine (catalogue name `dart`): `python -m pbdval.external.dart`.
Importing this package imports nothing else; engine.py loads dartpy (docs/engine-dart.md)."""
