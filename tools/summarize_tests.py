#!/usr/bin/env python3
"""Counts test cases in the JUnit XML files under a directory (gtest, rostest, pytest) and prints
the failures by name, then one closing line: "N passed, N failed, N skipped".

Each case is counted once. A rostest writes two files: rostest-*.xml with one case for the whole
run (classname rostest.runner.RosTest), which passes whenever the test node wrote its results,
and rosunit-*.xml (or a gtest file) with the test node's own cases. The run's case is counted only
when it did not pass (the fixture did not launch, the time limit ran out, no results were
written): then it stands for the inner cases, which are missing.

Exit status 1 when anything failed or no test ran at all."""
import os
import sys
import xml.etree.ElementTree as ET

ROSTEST_RUN_CLASS = 'rostest.runner.RosTest'


def cases(path):
    """(name, outcome, first line of the failure) of each case in the file; a rostest run's own
    case only when it did not pass."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        yield ('%s' % path, 'failed', 'unreadable result file: %s' % e)
        return
    for case in root.iter('testcase'):
        name = '%s.%s' % (case.get('classname', ''), case.get('name', ''))
        failure = case.find('failure')
        if failure is None:
            failure = case.find('error')
        if failure is not None:
            text = (failure.get('message') or failure.text or '').strip().splitlines()
            yield (name, 'failed', text[0] if text else '')
        elif case.get('classname') == ROSTEST_RUN_CLASS:
            continue  # its test node's cases are counted from their own file
        elif case.find('skipped') is not None or case.get('status') == 'notrun':
            yield (name, 'skipped', '')
        else:
            yield (name, 'passed', '')


def main():
    top = sys.argv[1] if len(sys.argv) > 1 else 'build/test_results'
    counts = {'passed': 0, 'failed': 0, 'skipped': 0}
    failures = []
    for dirpath, _, files in os.walk(top):
        for f in sorted(files):
            if not f.endswith('.xml'):
                continue
            path = os.path.join(dirpath, f)
            for name, outcome, why in cases(path):
                counts[outcome] += 1
                if outcome == 'failed':
                    failures.append('  FAILED %s (%s) %s' % (name, os.path.relpath(path, top), why))
    if failures:
        print('Failures:')
        print('\n'.join(failures))
    print('%d passed, %d failed, %d skipped' % (counts['passed'], counts['failed'],
                                                counts['skipped']))
    return 1 if counts['failed'] or counts['passed'] == 0 else 0


if __name__ == '__main__':
    sys.exit(main())
