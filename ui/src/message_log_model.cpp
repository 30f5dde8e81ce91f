#include "vaw/ui/message_log_model.hpp"

#include <QStringList>
#include <QStyle>

#include "standard_icon.hpp"

namespace vaw::ui {

namespace {

QString severityName(MessageLogModel::Severity s) {
  switch (s) {
    case MessageLogModel::Severity::Info: return MessageLogModel::tr("Info");
    case MessageLogModel::Severity::Warning: return MessageLogModel::tr("Warning");
    case MessageLogModel::Severity::Error: return MessageLogModel::tr("Error");
  }
  return {};
}

}  // namespace

MessageLogModel::MessageLogModel(QObject* parent) : QAbstractTableModel(parent) {}

void MessageLogModel::add(Severity severity, const QString& text, const QString& detail) {
  if (static_cast<int>(messages_.size()) >= kMaxMessages) {
    beginRemoveRows({}, 0, 0);
    messages_.pop_front();
    endRemoveRows();
  }
  const int row = static_cast<int>(messages_.size());
  beginInsertRows({}, row, row);
  messages_.push_back(Message{severity, text, detail, QDateTime::currentDateTime()});
  endInsertRows();
  emit messageAdded(severity, text);
}

void MessageLogModel::add(const vaw::Diagnostic& d) {
  QStringList detail;
  if (!d.file.empty()) detail << tr("File: %1").arg(QString::fromStdString(d.file));
  if (!d.field.empty()) detail << tr("Field: %1").arg(QString::fromStdString(d.field));
  if (!d.expected.empty()) detail << tr("Expected: %1").arg(QString::fromStdString(d.expected));
  if (!d.found.empty()) detail << tr("Found: %1").arg(QString::fromStdString(d.found));
  add(d.severity == vaw::Diagnostic::Severity::Error ? Severity::Error : Severity::Warning,
      QString::fromStdString(d.message()), detail.join(QLatin1Char('\n')));
}

void MessageLogModel::clear() {
  beginResetModel();
  messages_.clear();
  endResetModel();
}

int MessageLogModel::count(Severity severity) const {
  int n = 0;
  for (const auto& m : messages_) n += m.severity == severity ? 1 : 0;
  return n;
}

QString MessageLogModel::text(int row) const {
  return row >= 0 && row < static_cast<int>(messages_.size()) ? messages_[static_cast<std::size_t>(row)].text
                                                               : QString();
}

int MessageLogModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : static_cast<int>(messages_.size());
}

int MessageLogModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant MessageLogModel::data(const QModelIndex& index, int role) const {
  if (!checkIndex(index, CheckIndexOption::IndexIsValid | CheckIndexOption::ParentIsInvalid)) return {};
  const Message& m = messages_[static_cast<std::size_t>(index.row())];
  switch (role) {
    case Qt::DisplayRole:
      return index.column() == SeverityColumn ? severityName(m.severity) : m.text;
    case Qt::ToolTipRole: {
      QString tip = m.time.toString(Qt::ISODate) + QLatin1Char('\n') + m.text;
      if (!m.detail.isEmpty()) tip += QLatin1Char('\n') + m.detail;
      return tip;
    }
    case Qt::DecorationRole: {
      if (index.column() != SeverityColumn) return {};
      switch (m.severity) {
        case Severity::Info: return standardIcon(QStyle::SP_MessageBoxInformation);
        case Severity::Warning: return standardIcon(QStyle::SP_MessageBoxWarning);
        case Severity::Error: return standardIcon(QStyle::SP_MessageBoxCritical);
      }
      return {};
    }
    default: return {};
  }
}

QVariant MessageLogModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || role != Qt::DisplayRole) return {};
  switch (section) {
    case SeverityColumn: return tr("Severity");
    case MessageColumn: return tr("Message");
    default: return {};
  }
}

}  // namespace vaw::ui
