

class TestDissectUniversalRobots:
    '''The dissectors of a Universal Robots cell (packet-ur*.c, packet-rtde.c, packet-robotiq-gripper.c),
    on a capture holding every interface once: which frames each protocol claims, and a field of each.'''

    # Ports 30001-30004 are MRCPv2's too: name the cell's protocols on them.
    DECODE_AS = ('-d', 'tcp.port==30001,ur', '-d', 'tcp.port==30003,ur_realtime', '-d', 'tcp.port==30004,rtde')
    FRAMES = {
        'ur': '34',
        'ur_realtime': '35',
        'rtde': '36 37 58 59 80 81 96 97 108 109 118 119 127 128 134 140 145 148 150 152 154 156 158 160 162 164',
        'ur_dashboard': '38 60 82 98 110',
        'ur_reverse': '39',
        'ur_script_sender': '40 62',
        'ur_trajectory': '41 63',
        'ur_script_command': '42',
        'ur_interpreter': '43 65 87 101',
        'robotiq_gripper': '44 66 88 102 112 122 130 136',
    }

    def fields(self, cmd_tshark, capture_file, test_env, display_filter, *fields):
        return subprocess.check_output((cmd_tshark,
                '-r', capture_file('ur-cell-session.pcapng'),
                *self.DECODE_AS,
                '-Y', display_filter,
                '-T', 'fields', *[a for f in fields for a in ('-e', f)],
            ), encoding='utf-8', env=test_env)

    def test_ur_cell_frames(self, cmd_tshark, capture_file, test_env):
        '''Each interface's frames, by its protocol.'''
        for protocol, frames in self.FRAMES.items():
            stdout = self.fields(cmd_tshark, capture_file, test_env, protocol, 'frame.number')
            assert stdout.split() == frames.split(), protocol

    def test_ur_cell_fields(self, cmd_tshark, capture_file, test_env):
        '''The primary interface's version, and an RTDE request linked with its reply.'''
        stdout = self.fields(cmd_tshark, capture_file, test_env, 'ur', 'ur.version.major_version',
                             'ur.version.minor_version')
        assert stdout.split() == ['5', '11']
        stdout = self.fields(cmd_tshark, capture_file, test_env, 'rtde.response_to', 'frame.number', 'rtde.response_to')
        assert stdout.split('\n')[0].split('\t') == ['58', '36']
